// Reading the fields of a parsed JSON document (nlohmann::json) without
// letting a malformed one throw: each accessor checks the kind of the value,
// and the first failure is kept as an error naming the file, the field's path
// and what was expected, e.g.
//   "atlas.json: field 'lines[3].covariance': expected an array of 4 numbers, got [1,2]"
// After a failure the accessors return zeros; check status() before using
// what they returned. The JSON readers of every module use it (the atlas, the
// service's saved state, the intrinsics report summary).
#ifndef GROUNDLINE_CORE_JSON_FIELDS_H_
#define GROUNDLINE_CORE_JSON_FIELDS_H_

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "groundline/core/status.h"

namespace groundline::core {

// Parses a whole file as JSON into *out: an error naming the file (and
// `what` it should be) for a file that cannot be read or is not JSON,
// including numbers out of double's range.
Status ReadJsonFile(const std::filesystem::path& path, const std::string& what,
                    nlohmann::json* out);

// The value as an integer when it is a number, integral and within
// [min, max]; compared as a double before any cast (nlohmann's get<int>()
// casts 1e30 as it is, undefined behaviour).
std::optional<std::int64_t> JsonInteger(const nlohmann::json& value, std::int64_t min,
                                        std::int64_t max);

class JsonFieldReader {
 public:
  // `file`: how errors name the document (a file name or path).
  explicit JsonFieldReader(std::string file) : file_(std::move(file)) {}

  // `path` is the field's prefix ("" or "lines[3]."); `key` the member.
  const nlohmann::json* Get(const nlohmann::json& object, const std::string& path,
                            const char* key);
  double Number(const nlohmann::json& object, const std::string& path, const char* key);
  // A number that must also be finite.
  double Finite(const nlohmann::json& object, const std::string& path, const char* key);
  // An id: an integral number within +-2^53 (every such double is exact).
  std::int64_t Id(const nlohmann::json& object, const std::string& path, const char* key);
  std::vector<double> Numbers(const nlohmann::json& object, const std::string& path,
                              const char* key, std::size_t count);
  std::string String(const nlohmann::json& object, const std::string& path, const char* key);
  // Records `field`: expected `expected`, got `got` (a JSON dump is cut to 60 characters).
  void Fail(const std::string& field, const std::string& expected, const std::string& got);

  const Status& status() const { return status_; }
  bool ok() const { return status_.ok(); }

 private:
  std::int64_t IntegerIn(const nlohmann::json& object, const std::string& path, const char* key,
                         std::int64_t min, std::int64_t max, const std::string& expected);

  std::string file_;
  Status status_ = Status::Ok();
};

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_JSON_FIELDS_H_
