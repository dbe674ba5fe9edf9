#include "groundline/io/carmen_trajectory.h"

#include <string>

namespace groundline::io {

core::Status CarmenTrajectoryOptions::Validate() const {
  if (laser_id.has_value() && *laser_id < 0) {
    return core::Status::Error(
        "CarmenTrajectoryOptions: laser_id must be >= 0 (or unset for "
        "every laser), got " +
        std::to_string(*laser_id));
  }
  return core::Status::Ok();
}

core::Result<core::Trajectory> CarmenScanTrajectory(const CarmenLog& log,
                                                    const CarmenTrajectoryOptions& options) {
  if (core::Status valid = options.Validate(); !valid.ok()) return valid;
  core::Trajectory trajectory;
  trajectory.reserve(log.scans.size());
  const CarmenLaserScan* previous = nullptr;
  for (const CarmenLaserScan& scan : log.scans) {
    if (options.laser_id.has_value() && scan.laser_id != *options.laser_id) continue;
    const std::optional<core::SE2>& pose =
        options.pose_source == CarmenPoseSource::kOdometry ? scan.robot_pose : scan.laser_pose;
    if (!pose.has_value()) continue;
    if (previous != nullptr && !(scan.stamp_s > previous->stamp_s)) {
      return core::Status::Error(
          "CARMEN scan trajectory: ipc_timestamp " + std::to_string(scan.stamp_s) + " of " +
          CarmenLaserMessageName(scan) + " at line " + std::to_string(scan.line) +
          " does not follow " + std::to_string(previous->stamp_s) + " of " +
          CarmenLaserMessageName(*previous) + " at line " + std::to_string(previous->line) +
          "; select a single laser with CarmenTrajectoryOptions::laser_id");
    }
    core::StampedPose stamped;
    stamped.stamp_s = scan.stamp_s;
    stamped.pose = *pose;
    trajectory.push_back(stamped);
    previous = &scan;
  }
  return trajectory;
}

}  // namespace groundline::io
