// The self-calibration's state on disk: the running mount estimate a vehicle
// carries across restarts (the service writes it after every update and
// reads it when it starts). A load that pitched the camera in the evening is
// still on the forks in the morning; starting again from the commissioned
// mount would throw away what the estimator had learnt and re-raise nothing
// it knew (a knocked camera stays alarmed until it is recommissioned).
//
// The file names the commissioned mount the estimate was made against: a
// camera recommissioned since (another calibration file) makes the saved
// estimate meaningless, and Restore refuses it.
//
//   {"format": "groundline-mount-estimate", "version": 1,
//    "commissioned": {"pitch_deg", "roll_deg", "height_m", "yaw_deg", "forward_m", "lateral_m"},
//    "estimate":     {the same six},
//    "covariance": [16 numbers, row-major over (pitch_rad, roll_rad, height_m, yaw_rad)],
//    "alarm": false, "alarm_message": "", "frames": N, "windows_used": N, "steps": N,
//    "last_update_s": t}
//
// Angles in degrees in the extrinsics file's convention (docs/extrinsics.md).
#ifndef GROUNDLINE_CALIBRATION_MOUNT_ESTIMATE_FILE_H_
#define GROUNDLINE_CALIBRATION_MOUNT_ESTIMATE_FILE_H_

#include <filesystem>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/mount_self_calibration.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct SavedMountEstimate {
  CameraMount commissioned;  // the mount the estimate was made against
  MountEstimate estimate;
};

// Written atomically (temporary file, then rename).
core::Status WriteMountEstimate(const std::filesystem::path& path,
                                const SavedMountEstimate& saved);
// Errors name the file and the field: not JSON, another format or version, a
// value missing or not finite, an invalid mount, a covariance that is not
// symmetric positive definite.
core::Result<SavedMountEstimate> ReadMountEstimate(const std::filesystem::path& path);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_MOUNT_ESTIMATE_FILE_H_
