// The raw-odometry trajectory of a CARMEN log: one pose per laser scan.
//
// This is the "raw odometry" baseline of the Kuemmerle et al. 2009 benchmark
// (see ../shared/data/README.md): for every laser line that carries a pose
// (FLASER, RLASER, ROBOTLASERk; RAWLASERk carries none), a StampedPose at the
// line's ipc_timestamp holding the odometry pose written in that same line.
// The .relations files are keyed by the same ipc_timestamps, so a relation's
// t1 / t2 finds its scan by nearest stamp.
//
// Frames: by default the pose is the robot's odometry pose T_odom_base (the
// second pose of a FLASER line, `odom_x odom_y odom_theta`; `robot_pose_*` of
// ROBOTLASER). With pose_source = kLaser it is the laser's pose T_odom_laser
// (the first pose). In aces.clf and mit-csail.clf both are equal; in
// fr-clinic_robotlaser.clf the laser is 0.22 m ahead of the base. The
// trajectory's frame is the log's odometry frame, not a map frame.
#ifndef GROUNDLINE_IO_CARMEN_TRAJECTORY_H_
#define GROUNDLINE_IO_CARMEN_TRAJECTORY_H_

#include <optional>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/io/carmen.h"

namespace groundline::io {

enum class CarmenPoseSource {
  kOdometry,  // T_odom_base: odom_x odom_y odom_theta / robot_pose_*
  kLaser,     // T_odom_laser: x y theta / laser_pose_*
};

struct CarmenTrajectoryOptions {
  CarmenPoseSource pose_source = CarmenPoseSource::kOdometry;
  // Take only scans of this CARMEN laser number (1 = front: FLASER,
  // ROBOTLASER1; 2 = rear: RLASER, ROBOTLASER2). nullopt: every laser, which
  // in a log with several lasers usually breaks the strictly increasing
  // stamps and is then an error.
  std::optional<int> laser_id = 1;

  core::Status Validate() const;
};

// One StampedPose per selected scan, in file order, without covariance.
// Error if two consecutive selected scans do not have strictly increasing
// ipc_timestamps (core::Trajectory's invariant); the message names both
// lines. An empty result is not an error (e.g. a log of RAWLASER lines only).
core::Result<core::Trajectory> CarmenScanTrajectory(const CarmenLog& log,
                                                    const CarmenTrajectoryOptions& options = {});

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_CARMEN_TRAJECTORY_H_
