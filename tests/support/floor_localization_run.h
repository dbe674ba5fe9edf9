// Shared by the floor-localization tests: a short simulated zone drive
// (sim::FloorDrive, observations from the floor map, not the extractor)
// through the sliding-window smoother, with per-keyframe errors against the
// ground truth and the odometry-only baseline.
#ifndef GROUNDLINE_TESTS_SUPPORT_FLOOR_LOCALIZATION_RUN_H_
#define GROUNDLINE_TESTS_SUPPORT_FLOOR_LOCALIZATION_RUN_H_

#include <Eigen/Cholesky>
#include <cmath>
#include <vector>

#include "groundline/localization/sliding_window_smoother.h"
#include "groundline/sim/floor_drive.h"
#include "groundline/sim/route.h"
#include "groundline/sim/sim_run.h"
#include "groundline/sim/zones.h"

namespace groundline::testing {

struct ZoneDrive {
  core::FloorMap map;
  core::Trajectory trajectory;
};

// The first duration_s of a route loop of about 200 m.
inline ZoneDrive MakeZoneDrive(sim::Zone zone, std::uint64_t seed, double duration_s) {
  const sim::World world = sim::BuildZone(zone, seed).value();
  sim::RouteOptions route_options;
  route_options.seed = seed;
  route_options.length_m = 200.0;
  route_options.length_tolerance_fraction = 0.9;
  route_options.sample_rate_hz = 50.0;
  const core::Result<sim::Route> route = sim::GenerateRoute(world, route_options);
  if (!route.ok()) {
    ADD_FAILURE() << route.message();
    return {};
  }
  core::Trajectory trajectory;
  for (const core::StampedPose& pose : route->T_map_base) {
    if (pose.stamp_s - route->T_map_base.front().stamp_s > duration_s) break;
    trajectory.push_back(pose);
  }
  return {sim::ToFloorMap(world), trajectory};
}

// The drive of the tests: the camera footprint widened to +-1.25 m so that the
// zone B aisle tapes (1.03 m from the aisle centre) are in view.
inline sim::FloorDriveOptions TestDriveOptions(std::uint64_t seed) {
  sim::FloorDriveOptions options;
  options.seed = seed;
  options.observations.half_width_m = 1.25;
  return options;
}

struct RunErrors {
  std::vector<double> position_m;     // per keyframe, fused
  std::vector<double> along_track_m;  // |error along the true heading|, fused
  std::vector<double> odometry_along_track_m;
  std::vector<double> odometry_position_m;
  std::vector<double> nees;  // 3-dof, e = Log(T_est^-1 T_true)
  int keyframes = 0;
  int lines_used = 0;
  int lines_rejected = 0;
  int junctions_used = 0;
  int landmarks_added = 0;
  int max_window = 0;

  static double Rms(const std::vector<double>& v) {
    double sum = 0.0;
    for (double x : v) sum += x * x;
    return v.empty() ? 0.0 : std::sqrt(sum / v.size());
  }
  static double Max(const std::vector<double>& v) {
    double m = 0.0;
    for (double x : v) m = std::max(m, std::abs(x));
    return m;
  }
  double NeesShare(double bound) const {
    int inside = 0;
    for (double x : nees) inside += x <= bound ? 1 : 0;
    return nees.empty() ? 0.0 : static_cast<double>(inside) / nees.size();
  }
};

// Runs the drive through a smoother (initialized at the true start pose with
// a 1 cm / 0.5 deg prior).
inline RunErrors RunSmoother(const ZoneDrive& drive, const sim::FloorDriveOptions& drive_options,
                             localization::SlidingWindowSmoother* smoother) {
  if (drive.trajectory.size() < 2) return {};
  sim::FloorDrive floor_drive(drive.map, drive.trajectory, drive_options);
  const core::SE2 start = floor_drive.Start().pose;
  smoother->Initialize(floor_drive.Start().stamp_s, start,
                       Eigen::Vector3d(1e-4, 1e-4, 7.6e-5).asDiagonal());
  core::SE2 odometry_pose = start;
  RunErrors errors;
  sim::DriveKeyframe keyframe;
  while (floor_drive.Next(&keyframe)) {
    const auto health =
        smoother->AddKeyframe(keyframe.stamp_s, keyframe.motion, keyframe.observations);
    if (!health.ok()) {
      ADD_FAILURE() << health.message();
      break;
    }
    ++errors.keyframes;
    errors.lines_used += health->lines_used;
    errors.lines_rejected += health->lines_rejected;
    errors.junctions_used += health->junctions_used;
    errors.landmarks_added += health->landmarks_added;
    errors.max_window = std::max(errors.max_window, health->window_size);
    const localization::PoseEstimate& estimate = smoother->Latest();
    const core::SE2& truth = keyframe.T_map_base_true;
    const Eigen::Vector2d heading(std::cos(truth.yaw()), std::sin(truth.yaw()));
    errors.position_m.push_back((estimate.T_map_base.translation() - truth.translation()).norm());
    errors.along_track_m.push_back(
        heading.dot(estimate.T_map_base.translation() - truth.translation()));
    odometry_pose = odometry_pose * keyframe.motion.T_start_end;
    errors.odometry_position_m.push_back(
        (odometry_pose.translation() - truth.translation()).norm());
    errors.odometry_along_track_m.push_back(
        heading.dot(odometry_pose.translation() - truth.translation()));
    const Eigen::Vector3d e = truth.Minus(estimate.T_map_base);
    errors.nees.push_back(e.dot(estimate.covariance.ldlt().solve(e)));
  }
  return errors;
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_SUPPORT_FLOOR_LOCALIZATION_RUN_H_
