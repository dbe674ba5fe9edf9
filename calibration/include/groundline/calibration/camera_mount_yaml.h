// The groundline camera extrinsics file: a CameraMount as YAML (yaml-cpp).
// The format, its keys and units are documented in docs/extrinsics.md:
//
//   format: groundline_camera_extrinsics
//   version: 1
//   height_m: 0.58
//   pitch_deg: 42.4
//   roll_deg: 0
//   yaw_deg: 0
//   forward_m: 0.42
//   lateral_m: 0
//
// Angles are stored in degrees in the file and in radians in CameraMount.
// Every key is required; unknown keys are rejected (a misspelt key would
// otherwise silently leave a default in place). Errors name the file, the line
// and the key, e.g. "mount.yaml:5: key 'height_m': expected a number, got 'abc'".
#ifndef GROUNDLINE_CALIBRATION_CAMERA_MOUNT_YAML_H_
#define GROUNDLINE_CALIBRATION_CAMERA_MOUNT_YAML_H_

#include <filesystem>
#include <string>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

inline constexpr char kCameraMountFormat[] = "groundline_camera_extrinsics";
inline constexpr int kCameraMountVersion = 1;

// Parses the text of an extrinsics file; source_name names it in messages.
core::Result<CameraMount> ParseCameraMountYaml(const std::string& yaml_text,
                                               const std::string& source_name);

// Reads and parses an extrinsics file.
core::Result<CameraMount> ReadCameraMountYaml(const std::filesystem::path& path);

// The file text for a valid mount (asserted), numbers in their shortest form
// that reads back to the same double (angles: the same degrees value).
std::string CameraMountToYaml(const CameraMount& mount);

// Writes the file atomically: PATH.tmp first, then renamed over PATH. Fails
// (leaving PATH untouched) if the mount is invalid or the file cannot be written.
core::Status WriteCameraMountYaml(const CameraMount& mount, const std::filesystem::path& path);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_CAMERA_MOUNT_YAML_H_
