#include "groundline/core/yaml_fields.h"

#include <cmath>
#include <set>
#include <vector>

#include "groundline/core/text_parse.h"

namespace groundline::core::internal {
namespace {

std::size_t LineOf(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : static_cast<std::size_t>(mark.line) + 1;
}

std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined()) return "nothing";
  if (node.IsScalar()) return node.Scalar();
  if (node.IsMap()) return "a mapping";
  if (node.IsSequence()) return "a sequence";
  return "an empty value";
}

}  // namespace

std::string JoinPath(std::string_view parent, std::string_view key) {
  if (parent.empty()) return std::string(key);
  return std::string(parent) + "." + std::string(key);
}

std::string IndexPath(std::string_view parent, std::size_t index) {
  return std::string(parent) + "[" + std::to_string(index) + "]";
}

std::size_t LineOfPath(const YAML::Node& root, std::string_view path) {
  // Walks with const lookups and Node::reset: operator= on a YAML::Node would
  // assign into the document, and a non-const operator[] would insert keys.
  YAML::Node node;
  node.reset(root);
  std::size_t line = LineOf(root);
  for (std::string_view part : SplitDelimited(path, '.')) {
    std::vector<std::size_t> indices;
    const std::size_t bracket = part.find('[');
    const std::string key(part.substr(0, bracket));
    for (std::size_t b = bracket; b != std::string_view::npos; b = part.find('[', b + 1)) {
      const std::size_t close = part.find(']', b);
      if (close == std::string_view::npos) return line;
      const std::optional<std::int64_t> i = ParseInt(part.substr(b + 1, close - b - 1));
      if (!i || *i < 0) return line;
      indices.push_back(static_cast<std::size_t>(*i));
    }
    const YAML::Node& current = node;
    if (!current.IsMap() || !current[key]) return line;
    node.reset(current[key]);
    line = LineOf(node);
    for (std::size_t i : indices) {
      const YAML::Node& sequence = node;
      if (!sequence.IsSequence() || i >= sequence.size()) return line;
      node.reset(sequence[i]);
      line = LineOf(node);
    }
  }
  return line;
}

Result<YAML::Node> LoadYamlFile(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    return Status::Error("cannot open " + path.string() + ": no such file");
  }
  try {
    return YAML::LoadFile(path.string());
  } catch (const YAML::Exception& e) {
    const std::size_t line = e.mark.is_null() ? 0 : static_cast<std::size_t>(e.mark.line) + 1;
    return Status::Error(path.string() + ":" + std::to_string(line) +
                         ": YAML syntax error: " + e.msg);
  }
}

std::string YamlExceptionMessage(std::string_view source, const YAML::Exception& e) {
  std::string message(source);
  if (!e.mark.is_null()) message += ":" + std::to_string(e.mark.line + 1);
  return message + ": unexpected YAML structure: " + e.msg;
}

void YamlFields::Fail(const YAML::Node& at, std::string_view path, std::string_view expected,
                      std::string_view got) {
  Fail(LineOf(at), path, expected, got);
}

void YamlFields::Fail(std::size_t line, std::string_view path, std::string_view expected,
                      std::string_view got) {
  if (status_.ok()) status_ = Status::Error(FieldError(file_, line, path, expected, got));
}

bool YamlFields::ExpectMap(const YAML::Node& node, std::string_view path) {
  if (node.IsMap()) return true;
  Fail(node, path, "a mapping of keys to values", Describe(node));
  return false;
}

bool YamlFields::ExpectSequence(const YAML::Node& node, std::string_view path) {
  if (node.IsSequence()) return true;
  Fail(node, path, "a sequence", Describe(node));
  return false;
}

void YamlFields::CheckKeys(const YAML::Node& map, std::string_view path,
                           std::initializer_list<std::string_view> allowed) {
  CheckKeys(map, path, std::vector<std::string_view>(allowed));
}

void YamlFields::CheckKeys(const YAML::Node& map, std::string_view path,
                           const std::vector<std::string_view>& allowed) {
  std::set<std::string> seen;
  for (const auto& entry : map) {
    const std::string key = entry.first.Scalar();
    if (!seen.insert(key).second) {
      Fail(entry.first, JoinPath(path, key), "each key once", "a duplicate key");
    }
    bool known = false;
    for (std::string_view name : allowed) known = known || name == key;
    if (!known && strict_) {
      std::string names;
      for (std::string_view name : allowed)
        names += (names.empty() ? "" : ", ") + std::string(name);
      Fail(entry.first, JoinPath(path, key), "one of the keys " + names, "an unknown key");
    }
  }
}

YAML::Node YamlFields::Child(const YAML::Node& map, std::string_view path, const char* key,
                             bool required) {
  if (!map.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  const YAML::Node child = map[key];
  if (!child && required) Fail(map, JoinPath(path, key), "a value", "nothing (missing key)");
  return child;
}

std::string YamlFields::Text(const YAML::Node& map, std::string_view path, const char* key,
                             bool allow_empty) {
  const YAML::Node node = Child(map, path, key);
  if (!node) return {};
  if (node.IsNull() && allow_empty) return {};
  if (!node.IsScalar() || (!allow_empty && node.Scalar().empty())) {
    Fail(node, JoinPath(path, key), allow_empty ? "a string" : "a non-empty string",
         Describe(node));
    return {};
  }
  if (!IsValidUtf8(node.Scalar())) {
    Fail(node, JoinPath(path, key), "UTF-8 text", "bytes that are not UTF-8");
    return {};
  }
  return node.Scalar();
}

double YamlFields::NumberAt(const YAML::Node& node, std::string_view path) {
  const std::optional<double> value =
      node.IsScalar() ? ParseDouble(node.Scalar()) : std::optional<double>();
  if (!value || !std::isfinite(*value)) {
    Fail(node, path, "a finite number", Describe(node));
    return 0.0;
  }
  return *value;
}

std::int64_t YamlFields::IntegerAt(const YAML::Node& node, std::string_view path) {
  const std::optional<std::int64_t> value =
      node.IsScalar() ? ParseInt(node.Scalar()) : std::optional<std::int64_t>();
  if (!value) {
    Fail(node, path, "an integer", Describe(node));
    return 0;
  }
  return *value;
}

bool YamlFields::BoolAt(const YAML::Node& node, std::string_view path) {
  if (node.IsScalar() && (node.Scalar() == "true" || node.Scalar() == "false")) {
    return node.Scalar() == "true";
  }
  Fail(node, path, "true or false", Describe(node));
  return false;
}

double YamlFields::Number(const YAML::Node& map, std::string_view path, const char* key) {
  const YAML::Node node = Child(map, path, key);
  return node ? NumberAt(node, JoinPath(path, key)) : 0.0;
}

std::int64_t YamlFields::Integer(const YAML::Node& map, std::string_view path, const char* key) {
  const YAML::Node node = Child(map, path, key);
  return node ? IntegerAt(node, JoinPath(path, key)) : 0;
}

void YamlFields::CheckFormat(const YAML::Node& root, std::string_view name, int major, int minor,
                             int* file_major, int* file_minor) {
  if (!ExpectMap(root, "(document)")) return;
  const std::string format = Text(root, "", "format");
  if (!ok()) return;
  if (format != name) {
    // Built piecewise: GCC 12 at -O3 warns (-Wrestrict, a false positive) on
    // "'" + std::string(name) + "'".
    std::string expected = "'";
    expected.append(name).append("'");
    Fail(root["format"], "format", expected, format);
    return;
  }
  const YAML::Node version = Child(root, "", "version");
  if (!version) return;
  const std::string text = version.IsScalar() ? version.Scalar() : Describe(version);
  const std::vector<std::string_view> parts = SplitDelimited(text, '.');
  const std::optional<std::int64_t> got_major = ParseInt(parts[0]);
  const std::optional<std::int64_t> got_minor =
      parts.size() == 2 ? ParseInt(parts[1]) : std::optional<std::int64_t>(0);
  const std::string supported = std::to_string(major) + ".x";
  if (parts.size() > 2 || !got_major || !got_minor || *got_major < 0 || *got_minor < 0) {
    Fail(version, "version", "MAJOR.MINOR, e.g. '" + std::to_string(major) + ".0'", text);
    return;
  }
  if (*got_major > major) {
    Fail(version, "version",
         "major version " + std::to_string(major) + " (this reader reads " + supported +
             "; the file was written by a newer groundline: upgrade groundline to read it)",
         text);
    return;
  }
  if (*got_major != major) {
    Fail(version, "version", "version " + supported + " (older versions are not supported)", text);
    return;
  }
  *file_major = static_cast<int>(*got_major);
  *file_minor = static_cast<int>(*got_minor);
  set_strict(*got_minor <= minor);
}

}  // namespace groundline::core::internal
