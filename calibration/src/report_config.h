// Reading one mapping of thresholds (`intrinsics_report:`, `floor_report:`)
// from a calibration config file, with errors that name the file, the line
// and the key.
#ifndef GROUNDLINE_CALIBRATION_SRC_REPORT_CONFIG_H_
#define GROUNDLINE_CALIBRATION_SRC_REPORT_CONFIG_H_

#include <filesystem>
#include <initializer_list>
#include <variant>

#include "groundline/core/status.h"

namespace groundline::calibration::internal {

struct ConfigField {
  const char* key;
  std::variant<double*, int*, bool*> target;  // written when the key is present
};

// Sets the fields present under `section` of the YAML file; a missing section
// leaves all fields as they are. Fails on an unreadable or malformed file, a
// section that is not a mapping, an unknown key or a value of the wrong type.
core::Status ReadConfigSection(const std::filesystem::path& path, const char* section,
                               std::initializer_list<ConfigField> fields);

}  // namespace groundline::calibration::internal

#endif  // GROUNDLINE_CALIBRATION_SRC_REPORT_CONFIG_H_
