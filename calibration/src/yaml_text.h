// Loading YAML text for the calibration readers, with a syntax error reported
// as "<source>:<line>: YAML syntax error: ...".
#ifndef GROUNDLINE_CALIBRATION_SRC_YAML_TEXT_H_
#define GROUNDLINE_CALIBRATION_SRC_YAML_TEXT_H_

#include <yaml-cpp/yaml.h>

#include <string>

#include "groundline/core/status.h"

namespace groundline::calibration::internal {

inline core::Result<YAML::Node> LoadYamlText(const std::string& yaml_text,
                                             const std::string& source_name) {
  try {
    return YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    return core::Status::Error(source_name + ":" + std::to_string(e.mark.line + 1) +
                               ": YAML syntax error: " + e.msg);
  }
}

}  // namespace groundline::calibration::internal

#endif  // GROUNDLINE_CALIBRATION_SRC_YAML_TEXT_H_
