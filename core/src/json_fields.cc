#include "groundline/core/json_fields.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace groundline::core {

using nlohmann::json;

Status ReadJsonFile(const std::filesystem::path& path, const std::string& what, json* out) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return Status::Error(path.string() + ": no such " + what + " (not a regular file)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path.string() + ": cannot open the " + what + " for reading");
  try {
    *out = json::parse(in);
  } catch (const json::exception& error) {  // parse_error, and out_of_range for 1e999
    return Status::Error(path.string() + ": not valid JSON, expected the " + what + " (" +
                         error.what() + ")");
  }
  return Status::Ok();
}

const json* JsonFieldReader::Get(const json& object, const std::string& path, const char* key) {
  if (!object.is_object() || !object.contains(key)) {
    Fail(path + key, "a value", "nothing (missing)");
    return nullptr;
  }
  return &object.at(key);
}

double JsonFieldReader::Number(const json& object, const std::string& path, const char* key) {
  const json* value = Get(object, path, key);
  if (value == nullptr) return 0.0;
  if (!value->is_number()) {
    Fail(path + key, "a number", value->dump());
    return 0.0;
  }
  return value->get<double>();
}

double JsonFieldReader::Finite(const json& object, const std::string& path, const char* key) {
  const double value = Number(object, path, key);
  if (!std::isfinite(value)) {
    Fail(path + key, "a finite number", std::to_string(value));
    return 0.0;
  }
  return value;
}

std::int64_t JsonFieldReader::Id(const json& object, const std::string& path, const char* key) {
  constexpr std::int64_t kExact = 9007199254740992;  // 2^53
  return IntegerIn(object, path, key, -kExact, kExact, "an integer id (integral, within +-2^53)");
}

std::optional<std::int64_t> JsonInteger(const json& value, std::int64_t min, std::int64_t max) {
  if (!value.is_number()) return std::nullopt;
  const double v = value.get<double>();
  if (!(v >= static_cast<double>(min) && v <= static_cast<double>(max)) || std::floor(v) != v) {
    return std::nullopt;
  }
  return static_cast<std::int64_t>(v);
}

std::int64_t JsonFieldReader::IntegerIn(const json& object, const std::string& path,
                                        const char* key, std::int64_t min, std::int64_t max,
                                        const std::string& expected) {
  Number(object, path, key);
  if (!ok()) return 0;
  const json& value = *Get(object, path, key);
  const std::optional<std::int64_t> integer = JsonInteger(value, min, max);
  if (!integer) {
    Fail(path + key, expected, value.dump());
    return 0;
  }
  return *integer;
}

std::vector<double> JsonFieldReader::Numbers(const json& object, const std::string& path,
                                             const char* key, std::size_t count) {
  const json* value = Get(object, path, key);
  std::vector<double> out(count, 0.0);
  if (value == nullptr) return out;
  if (!value->is_array() || value->size() != count) {
    Fail(path + key, "an array of " + std::to_string(count) + " numbers", value->dump());
    return out;
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!(*value)[i].is_number()) {
      Fail(path + key, "an array of numbers", value->dump());
      return out;
    }
    out[i] = (*value)[i].get<double>();
  }
  return out;
}

std::string JsonFieldReader::String(const json& object, const std::string& path,
                                    const char* key) {
  const json* value = Get(object, path, key);
  if (value == nullptr) return {};
  if (!value->is_string()) {
    Fail(path + key, "a string", value->dump());
    return {};
  }
  return value->get<std::string>();
}

void JsonFieldReader::Fail(const std::string& field, const std::string& expected,
                           const std::string& got) {
  if (!status_.ok()) return;
  const std::string shown = got.size() > 60 ? got.substr(0, 57) + "..." : got;
  status_ = Status::Error(file_ + ": field '" + field + "': expected " + expected + ", got " +
                          shown);
}

}  // namespace groundline::core
