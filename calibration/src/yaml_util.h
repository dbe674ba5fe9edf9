// yaml-cpp helpers for messages that name the file and line.
#ifndef GROUNDLINE_CALIBRATION_SRC_YAML_UTIL_H_
#define GROUNDLINE_CALIBRATION_SRC_YAML_UTIL_H_

#include <yaml-cpp/yaml.h>

#include <string>

namespace groundline::calibration::yaml_util {

// "<source>:<line>" of a node, or "<source>" when yaml-cpp has no mark.
inline std::string Where(const std::string& source, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? source : source + ":" + std::to_string(mark.line + 1);
}

// "<source>:<line of the key>: key '<key>'" for a key of the mapping `map`.
inline std::string KeyWhere(const YAML::Node& map, const std::string& source,
                            const std::string& key) {
  for (const auto& entry : map) {
    if (entry.first.IsScalar() && entry.first.Scalar() == key) {
      return Where(source, entry.first) + ": key '" + key + "'";
    }
  }
  return source + ": key '" + key + "'";
}

}  // namespace groundline::calibration::yaml_util

#endif  // GROUNDLINE_CALIBRATION_SRC_YAML_UTIL_H_
