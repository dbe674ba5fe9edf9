// Odometry poses for CARMEN laser lines that log none.
//
// RAWLASERk lines carry the ranges but no pose; the robot's motion is in
// ODOM lines, written at their own stamps (a different module, a different
// rate), so the scans fall between odometry readings. AttachOdometryPoses
// gives each such scan the odometry pose at its own stamp, interpolated
// between the ODOM readings around it (core::InterpolatePose), and its laser
// pose by the laser's mounting offset. Lines that log a pose (FLASER,
// ROBOTLASERk) keep theirs.
//
// What cannot be done is dropped and counted, never guessed:
//   - an ODOM reading stamped no later than the one kept before it
//     (`odometry_dropped`): the odometry is taken in stamp order, as a live
//     reader would;
//   - a scan before the first or after the last ODOM reading
//     (`scans_outside_odometry`): no extrapolation;
//   - a scan whose bracketing readings are more than max_gap_s apart
//     (`scans_in_gap`): the motion between them is unknown.
//
// Thread-safety: a pure function.
#ifndef GROUNDLINE_IO_CARMEN_ODOMETRY_H_
#define GROUNDLINE_IO_CARMEN_ODOMETRY_H_

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/io/carmen.h"

namespace groundline::io {

struct CarmenOdometryOptions {
  // The laser in the robot's base frame: CARMEN's robot_frontlaser_offset
  // is its x (CarmenFrontLaserOffset reads it from a log's PARAM lines).
  core::SE2 T_base_laser;
  // ODOM readings around a scan further apart than this leave it without a
  // pose. The Radish logs write ODOM at 10-40 Hz.
  double max_gap_s = 0.5;
  core::Status Validate() const;  // T_base_laser finite, max_gap_s finite and > 0
};

struct CarmenScansWithOdometry {
  // The scans given, in their order, with robot_pose and laser_pose set;
  // those that could not get one are left out (counted below).
  std::vector<CarmenLaserScan> scans;
  std::int64_t attached = 0;  // poses interpolated from ODOM readings
  std::int64_t odometry_dropped = 0;
  std::int64_t scans_outside_odometry = 0;
  std::int64_t scans_in_gap = 0;
  std::int64_t first_dropped_line = 0;  // the first scan left out (0: none)
};

// `scans` in any order; `odometry` in file order. Errors: invalid options,
// a null scan, or a non-finite stamp or pose.
core::Result<CarmenScansWithOdometry> AttachOdometryPoses(
    std::span<const CarmenLaserScan* const> scans, std::span<const CarmenOdometry> odometry,
    const CarmenOdometryOptions& options = {});

// The front laser's offset from a log's PARAM robot_frontlaser_offset (x
// forward, in metres), nullopt without one; an error names the parameter
// when its value is not a finite number.
core::Result<std::optional<double>> CarmenFrontLaserOffset(const CarmenLog& log);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_CARMEN_ODOMETRY_H_
