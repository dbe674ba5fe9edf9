// Where the `targets` and `calibrate` commands find calib_targets/targets.yaml
// when --targets-file is not given: ./calib_targets/targets.yaml if present,
// else the copy in the source tree groundline was built from.
#ifndef GROUNDLINE_TOOLS_CALIB_TARGETS_FILE_H_
#define GROUNDLINE_TOOLS_CALIB_TARGETS_FILE_H_

#include <filesystem>
#include <string>

namespace groundline::tools {

inline std::string DefaultCalibTargetsFile() {
  const std::filesystem::path local = "calib_targets/targets.yaml";
  if (std::filesystem::exists(local)) return local.string();
  return GROUNDLINE_SOURCE_CALIB_TARGETS_FILE;
}

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_CALIB_TARGETS_FILE_H_
