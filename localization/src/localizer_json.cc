#include "groundline/localization/localizer_json.h"

#include <numbers>

namespace groundline::localization {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

nlohmann::ordered_json RowMajor(const core::Matrix3& c) {
  return {c(0, 0), c(0, 1), c(0, 2), c(1, 0), c(1, 1), c(1, 2), c(2, 0), c(2, 1), c(2, 2)};
}

}  // namespace

std::string ModeName(const LocalizerOptions& options) {
  switch (options.mode) {
    case LocalizerMode::kOdometry:
      return "odometry";
    case LocalizerMode::kLidar:
      return "lidar";
    case LocalizerMode::kLines:
      return options.use_lidar ? "lines+lidar" : "lines";
    case LocalizerMode::kMapping:
      return options.use_lidar ? "mapping+lidar" : "mapping";
  }
  return "unknown";
}

void AddLidarJson(const lidar::ScanOdometryKeyframe& k, nlohmann::ordered_json* line) {
  const lidar::MatchInformation& info = k.information;
  (*line)["lidar_matched"] = k.matched;
  (*line)["lidar_score"] = k.match_score;
  (*line)["lidar_degenerate"] = k.degenerate;
  (*line)["lidar_fisher_degenerate"] = info.degenerate;
  (*line)["lidar_aliased"] = k.aliasing.aliased;
  (*line)["lidar_alias_score"] = k.aliasing.best_score;
  (*line)["lidar_alias_shift_m"] = k.aliasing.best_shift_m;
  (*line)["lidar_alias_evidence"] = k.aliasing.evidence;
  (*line)["lidar_rank"] = info.rank;
  (*line)["lidar_scaled_eigenvalues"] = {info.scaled_eigenvalues(0), info.scaled_eigenvalues(1),
                                         info.scaled_eigenvalues(2)};
  const core::Vector3& v = info.weakest_direction;
  (*line)["lidar_weakest_direction"] = {v(0), v(1), v(2)};
  const core::Vector2 v_map = k.T_odom_base.Rotation() * core::Vector2(v.head<2>());
  (*line)["lidar_weakest_direction_map"] = {v_map.x(), v_map.y(), v(2)};
  (*line)["lidar_relative_rank"] = k.relative_rank;
  if (k.relative) {
    // The measurement and its square-root information, row-major: enough to
    // check its consistency against ground truth offline.
    const core::SE2& Z = k.relative->T_prev_curr;
    (*line)["lidar_relative"] = {Z.x(), Z.y(), Z.yaw()};
    (*line)["lidar_relative_sqrt_information"] = RowMajor(k.relative->sqrt_information);
  }
}

nlohmann::ordered_json KeyframeJson(const KeyframeOutput& k, LocalizerMode mode) {
  nlohmann::ordered_json line;
  line["keyframe"] = k.index + 1;
  line["stamp_s"] = k.pose.stamp_s;
  if (k.frame_stamp_s) line["frame_stamp_s"] = *k.frame_stamp_s;
  line["x_m"] = k.pose.T_map_base.x();
  line["y_m"] = k.pose.T_map_base.y();
  line["yaw_deg"] = k.pose.T_map_base.yaw() * kDeg;
  if (mode == LocalizerMode::kOdometry) line["mode"] = "odometry";
  if (mode == LocalizerMode::kLidar) line["mode"] = "lidar";
  if (k.has_covariance) line["cov"] = RowMajor(k.pose.covariance);
  if (k.smoother) {
    const KeyframeHealth& health = *k.smoother;
    line["lines_observed"] = health.lines_observed;
    line["lines_used"] = health.lines_used;
    line["lines_rejected"] = health.lines_rejected;
    line["lines_ambiguous"] = health.lines_ambiguous;
    line["lines_dropped"] = k.lines_dropped;
    line["junctions_used"] = health.junctions_used;
    if (health.slip_gate) line["slip_gate"] = true;
    if (health.slip_from_relative) line["slip_from_relative"] = true;
    if (health.relative_rejected) line["lidar_relative_rejected"] = true;
    if (health.slip_from_relative || health.relative_rejected) {
      line["relative_chi2"] = health.relative_chi2;
      line["slip_residual_chi2"] = health.slip_residual_chi2;
    }
    line["landmarks_added"] = health.landmarks_added;
    if (health.landmarks_retired > 0) line["landmarks_retired"] = health.landmarks_retired;
    line["window_size"] = health.window_size;
    line["iterations"] = health.iterations;
    line["converged"] = health.converged;
    line["solve_ms"] = 1e3 * health.solve_time_s;
    line["update_ms"] = 1e3 * health.update_time_s;
  }
  if (!k.error.empty()) line["error"] = k.error;
  line["update_cpu_ms"] = 1e3 * k.update_cpu_s;
  if (k.lidar) AddLidarJson(*k.lidar, &line);
  if (k.walls) {
    line["walls_observed"] = k.walls->observed;
    line["walls_used"] = k.walls->used;
    line["walls_rejected"] = k.walls->observed - k.walls->used;
  }
  line["sensors"] = {{"camera_ok", k.sensors.camera_ok},
                     {"lidar_ok", k.sensors.lidar_ok},
                     {"camera_age_s", k.sensors.camera_age_s},
                     {"lidar_age_s", k.sensors.lidar_age_s},
                     {"odometry_frozen", k.sensors.odometry_frozen},
                     {"odometry_ok", k.sensors.odometry_ok},
                     {"degraded_mode", k.sensors.degraded_mode}};
  return line;
}

nlohmann::ordered_json AtlasMapperReportJson(const AtlasMapperReport& r) {
  return {{"keyframes", r.keyframes},
          {"scans", r.scans},
          {"scans_failed", r.scans_failed},
          {"loop_closures", r.loops},
          {"loop_closures_rejected", r.loops_rejected},
          {"sightings", r.sightings},
          {"sightings_ambiguous", r.sightings_ambiguous},
          {"floor_lines", r.lines},
          {"faces", r.faces},
          {"junctions", r.junctions},
          {"landmarks_dropped", r.landmarks_dropped},
          {"initial_cost", r.initial_cost},
          {"final_cost", r.final_cost},
          {"covariances", r.covariances},
          {"surveyed", r.surveyed},
          {"surveyed_matched", r.surveyed_matched},
          {"surveyed_ambiguous", r.surveyed_ambiguous}};
}

nlohmann::ordered_json CountersJson(const LocalizerCounters& c) {
  return {{"wheel_readings", c.wheel_readings},
          {"wheel_dropped_non_finite", c.wheel_dropped_non_finite},
          {"wheel_dropped_out_of_order", c.wheel_dropped_out_of_order},
          {"wheel_dropped_duplicate", c.wheel_dropped_duplicate},
          {"wheel_late_merged", c.wheel_late_merged},
          {"clock_jumps", c.clock_jumps},
          {"wheel_before_start", c.wheel_before_start},
          {"wheel_dropped_frozen", c.wheel_dropped_frozen},
          {"wheel_dropped_slip", c.wheel_dropped_slip},
          {"wheel_coasted", c.wheel_coasted},
          {"odometry_gaps", c.odometry_gaps},
          {"frames", c.frames},
          {"frames_used", c.frames_used},
          {"frames_skipped", c.frames_skipped},
          {"frames_superseded", c.frames_superseded},
          {"frames_unreadable", c.frames_unreadable},
          {"frames_dropped_late", c.frames_dropped_late},
          {"frames_dropped_ahead", c.frames_dropped_ahead},
          {"scans", c.scans},
          {"scans_dropped_bad", c.scans_dropped_bad},
          {"scans_dropped_out_of_order", c.scans_dropped_out_of_order},
          {"scans_before_start", c.scans_before_start},
          {"scans_dropped_ahead", c.scans_dropped_ahead},
          {"scans_matched", c.scans_matched},
          {"keyframes", c.keyframes},
          {"solve_failures", c.solve_failures},
          {"solves_unconverged", c.solves_unconverged},
          {"lidar_failures", c.lidar_failures},
          {"lidar_restarts", c.lidar_restarts},
          {"lidar_local_map_renewals", c.lidar_local_map_renewals},
          {"reinitializations", c.reinitializations},
          {"initial_poses_dropped_ahead", c.initial_poses_dropped_ahead},
          {"initial_poses_dropped_late", c.initial_poses_dropped_late},
          {"initial_poses_superseded", c.initial_poses_superseded},
          {"lines_used", c.lines_used},
          {"lines_rejected", c.lines_rejected},
          {"lines_dropped", c.lines_dropped},
          {"landmarks_born", c.landmarks_born},
          {"landmarks_retired", c.landmarks_retired},
          {"lidar_keyframes", c.lidar_keyframes},
          {"lidar_degenerate", c.lidar_degenerate},
          {"lidar_fisher_degenerate", c.lidar_fisher_degenerate},
          {"lidar_aliased", c.lidar_aliased},
          {"lidar_with_relative", c.lidar_with_relative},
          {"walls_observed", c.walls_observed},
          {"walls_used", c.walls_used},
          {"walls_ambiguous", c.walls_ambiguous}};
}

}  // namespace groundline::localization
