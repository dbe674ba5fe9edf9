#include "groundline/io/carmen_odometry.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include "groundline/core/text_parse.h"
#include "groundline/core/trajectory.h"
#include "groundline/core/trajectory_association.h"

namespace groundline::io {

core::Status CarmenOdometryOptions::Validate() const {
  if (!T_base_laser.Log().allFinite()) {
    return core::Status::Error("CarmenOdometryOptions.T_base_laser: expected a finite pose");
  }
  if (!std::isfinite(max_gap_s) || !(max_gap_s > 0.0)) {
    return core::Status::Error(
        "CarmenOdometryOptions.max_gap_s: expected a finite value > 0 s, got " +
        std::to_string(max_gap_s));
  }
  return core::Status::Ok();
}

core::Result<CarmenScansWithOdometry> AttachOdometryPoses(
    std::span<const CarmenLaserScan* const> scans, std::span<const CarmenOdometry> odometry,
    const CarmenOdometryOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  CarmenScansWithOdometry out;
  core::Trajectory readings;
  readings.reserve(odometry.size());
  for (const CarmenOdometry& o : odometry) {
    if (!std::isfinite(o.stamp_s) || !o.pose.Log().allFinite()) {
      return core::Status::Error("line " + std::to_string(o.line) +
                                 ": ODOM stamp or pose is not finite");
    }
    if (!readings.empty() && !(o.stamp_s > readings.back().stamp_s)) {
      ++out.odometry_dropped;
      continue;
    }
    readings.push_back({o.stamp_s, o.pose, std::nullopt});
  }
  out.scans.reserve(scans.size());
  for (const CarmenLaserScan* scan : scans) {
    if (scan == nullptr) return core::Status::Error("AttachOdometryPoses: a scan is null");
    if (!std::isfinite(scan->stamp_s)) {
      return core::Status::Error("line " + std::to_string(scan->line) +
                                 ": laser stamp is not finite");
    }
    if (scan->robot_pose && scan->laser_pose) {
      out.scans.push_back(*scan);
      continue;
    }
    // The readings around the scan: the first one after it and the one before.
    const auto after =
        std::upper_bound(readings.begin(), readings.end(), scan->stamp_s,
                         [](double t, const core::StampedPose& p) { return t < p.stamp_s; });
    bool keep = true;
    if (readings.empty() || after == readings.begin() ||
        (after == readings.end() && readings.back().stamp_s != scan->stamp_s)) {
      ++out.scans_outside_odometry;
      keep = false;
    } else if (after != readings.end() &&
               after->stamp_s - std::prev(after)->stamp_s > options.max_gap_s) {
      ++out.scans_in_gap;
      keep = false;
    }
    if (!keep) {
      if (out.first_dropped_line == 0) out.first_dropped_line = scan->line;
      continue;
    }
    CarmenLaserScan with = *scan;
    with.robot_pose = core::InterpolatePose(readings, scan->stamp_s);
    with.laser_pose = *with.robot_pose * options.T_base_laser;
    out.scans.push_back(std::move(with));
    ++out.attached;
  }
  return out;
}

core::Result<std::optional<double>> CarmenFrontLaserOffset(const CarmenLog& log) {
  const auto it = log.params.find("robot_frontlaser_offset");
  if (it == log.params.end()) return std::optional<double>();
  const std::optional<double> x = core::ParseDouble(it->second);
  if (!x || !std::isfinite(*x)) {
    return core::Status::Error("PARAM robot_frontlaser_offset: expected a number of metres, got '" +
                               it->second + "'");
  }
  return std::optional<double>(*x);
}

}  // namespace groundline::io
