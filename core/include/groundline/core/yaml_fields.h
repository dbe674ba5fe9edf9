// Helpers for groundline's YAML files (the dataset's manifest and floor map,
// the simulator's scenarios): typed, validated field access whose errors name
// the file, the line and the dotted field path, and the shared format/version
// header. Users link yaml-cpp themselves (core keeps it a private dependency);
// namespace internal: for groundline's own readers, not a stable API.
#ifndef GROUNDLINE_CORE_YAML_FIELDS_H_
#define GROUNDLINE_CORE_YAML_FIELDS_H_

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "groundline/core/status.h"

namespace groundline::core::internal {

// A semantic problem found in a value type, located by a dotted field path
// ("sensors.lidar.range_max_m", "markings[2].width_m"). Shared by the
// Validate() methods (no line) and the readers (line looked up in the YAML).
struct FieldProblem {
  std::string field;
  std::string expected;
  std::string got;
};

std::string JoinPath(std::string_view parent, std::string_view key);
std::string IndexPath(std::string_view parent, std::size_t index);

// The 1-based line of the node at `path` under `root`, or of its deepest
// existing ancestor.
std::size_t LineOfPath(const YAML::Node& root, std::string_view path);

// Parses a YAML file; syntax errors become "file:line: YAML syntax error: ...".
Result<YAML::Node> LoadYamlFile(const std::filesystem::path& path);

// The message for a yaml-cpp exception: "source:line: unexpected YAML
// structure: <yaml-cpp's reason>" (no line when yaml-cpp gives none).
std::string YamlExceptionMessage(std::string_view source, const YAML::Exception& e);

// Runs `parse` (a reader's walk over a document) and returns a yaml-cpp
// exception escaping it (operator[] on a scalar, as<T>() of a value that is
// not a T, ...) as an error naming `source` and the line: no reader lets one
// reach the user. `parse` returns a Result<T> or a Status (the return type).
template <typename Parse>
auto CatchYamlErrors(std::string_view source, Parse&& parse) -> decltype(parse()) {
  try {
    return parse();
  } catch (const YAML::Exception& e) {
    return Status::Error(YamlExceptionMessage(source, e));
  }
}

// Reads typed fields from a parsed document, keeping the first error:
// "<file>:<line>: field '<path>': expected <...>, got '<...>'". After an
// error, getters return empty values; check ok() once at the end of a section.
class YamlFields {
 public:
  explicit YamlFields(std::string file) : file_(std::move(file)) {}

  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }
  const std::string& file() const { return file_; }
  // In strict mode CheckKeys rejects keys it does not know.
  void set_strict(bool strict) { strict_ = strict; }

  void Fail(const YAML::Node& at, std::string_view path, std::string_view expected,
            std::string_view got);
  void Fail(std::size_t line, std::string_view path, std::string_view expected,
            std::string_view got);

  bool ExpectMap(const YAML::Node& node, std::string_view path);
  bool ExpectSequence(const YAML::Node& node, std::string_view path);
  // Duplicate keys are always errors; unknown ones in strict mode.
  void CheckKeys(const YAML::Node& map, std::string_view path,
                 std::initializer_list<std::string_view> allowed);
  void CheckKeys(const YAML::Node& map, std::string_view path,
                 const std::vector<std::string_view>& allowed);

  // The child `key` of the mapping `map` found at `path`. An absent child is
  // returned as an undefined node, and is an error if `required`.
  YAML::Node Child(const YAML::Node& map, std::string_view path, const char* key,
                   bool required = true);

  // Scalars of `map[key]` (all required unless said otherwise).
  std::string Text(const YAML::Node& map, std::string_view path, const char* key,
                   bool allow_empty = false);
  double Number(const YAML::Node& map, std::string_view path, const char* key);
  std::int64_t Integer(const YAML::Node& map, std::string_view path, const char* key);
  // A scalar node itself (a sequence element).
  double NumberAt(const YAML::Node& node, std::string_view path);
  std::int64_t IntegerAt(const YAML::Node& node, std::string_view path);
  // true/false (YAML 1.2 spelling).
  bool BoolAt(const YAML::Node& node, std::string_view path);

  // Checks `format: <name>` and `version: MAJOR[.MINOR]` at the top of `root`:
  // another name, or a major version other than `major`, is an error; a minor
  // version above `minor` turns strict mode off (newer files may add keys).
  void CheckFormat(const YAML::Node& root, std::string_view name, int major, int minor,
                   int* file_major, int* file_minor);

 private:
  std::string file_;
  bool strict_ = true;
  Status status_ = Status::Ok();
};

}  // namespace groundline::core::internal

#endif  // GROUNDLINE_CORE_YAML_FIELDS_H_
