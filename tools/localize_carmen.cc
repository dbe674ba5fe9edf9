#include "localize_carmen.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "groundline/core/angles.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/metric_fields.h"
#include "groundline/core/relation_metrics.h"
#include "groundline/core/text_parse.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/io/carmen.h"
#include "groundline/io/carmen_odometry.h"
#include "groundline/io/carmen_order.h"
#include "groundline/io/relations.h"
#include "groundline/localization/lidar/lidar_slam.h"
#include "progress.h"
#include "run_resources.h"
#include "run_summary.h"

namespace groundline::tools {
namespace {

namespace lidar = localization::lidar;

std::string Milliseconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.0f", seconds * 1e3);
  return text;
}

nlohmann::ordered_json HealthLine(const lidar::ScanReport& r, const core::SE2& T_map_base) {
  nlohmann::ordered_json line;
  line["stamp_s"] = r.stamp_s;
  line["x_m"] = T_map_base.x();
  line["y_m"] = T_map_base.y();
  line["yaw_deg"] = T_map_base.yaw() * core::kRadToDeg;
  line["local_x_m"] = r.T_local_base.x();
  line["local_y_m"] = r.T_local_base.y();
  line["local_yaw_deg"] = r.T_local_base.yaw() * core::kRadToDeg;
  line["matched"] = r.matched;
  line["velocity_prediction"] = r.velocity_prediction;
  line["score"] = r.match.score;
  line["correlative_score"] = r.match.correlative_score;
  line["points_used"] = r.match.points_used;
  line["points_rejected_free"] = r.match.points_rejected_free;
  const core::Vector3& e = r.information.scaled_eigenvalues;
  line["eigenvalues"] = {e(0), e(1), e(2)};
  line["rank"] = r.information.rank;
  line["degenerate"] = r.information.degenerate;
  const core::Vector3& d = r.information.weakest_direction;
  line["weakest_direction"] = {d(0), d(1), d(2)};
  line["keyframe"] = r.keyframe;
  line["loops_found"] = r.loops_found;
  line["loops_rejected_free_space"] = r.loops_rejected_free_space;
  return line;
}

}  // namespace

int LocalizeFail(const std::string& message) {
  std::fprintf(stderr, "groundline localize: %s\n", message.c_str());
  return 1;
}

int RunLocalizeCarmen(const LocalizeCarmenFlags& flags) {
  const auto wall_start = std::chrono::steady_clock::now();
  const double cpu_start = ProcessCpuSeconds();
  ProgressLine progress("localize");
  progress.Update("reading", 0.0);
  core::Result<io::CarmenLog> log = io::ReadCarmenLog(flags.log_path);
  if (!log.ok()) return LocalizeFail(log.message());
  RunWarnings warnings("localize");
  const io::CarmenReadSummary& read = log->summary;
  if (read.skipped_line_count > 0) {
    warnings.Add("skipped_lines", flags.log_path + ": skipped " +
                                      std::to_string(read.skipped_line_count) + " malformed line" +
                                      (read.skipped_line_count == 1 ? "" : "s") + " (first: line " +
                                      std::to_string(read.skipped_lines.front().line) + ": " +
                                      read.skipped_lines.front().reason +
                                      "); 'groundline convert carmen --strict' stops at each");
  }
  // Front-laser lines that log no pose (RAWLASER1) get the odometry's pose
  // at their stamp, interpolated between the ODOM lines around them.
  std::vector<const io::CarmenLaserScan*> front;
  bool without_pose = false;
  for (const io::CarmenLaserScan& s : log->scans) {
    if (s.laser_id != 1) continue;
    front.push_back(&s);
    without_pose = without_pose || !(s.robot_pose && s.laser_pose);
  }
  io::CarmenScansWithOdometry posed;
  std::vector<const io::CarmenLaserScan*> read_scans;
  if (without_pose) {
    core::Result<std::optional<double>> offset = io::CarmenFrontLaserOffset(*log);
    if (!offset.ok()) return LocalizeFail(flags.log_path + ": " + offset.message());
    io::CarmenOdometryOptions odometry_options;
    if (*offset) {
      odometry_options.T_base_laser = core::SE2(**offset, 0.0, 0.0);
    } else {
      warnings.Add("laser_offset", flags.log_path +
                                       ": RAWLASER1 lines and no PARAM robot_frontlaser_offset: "
                                       "the laser is taken to sit at the robot's origin");
    }
    core::Result<io::CarmenScansWithOdometry> attached =
        io::AttachOdometryPoses(front, log->odometry, odometry_options);
    if (!attached.ok()) return LocalizeFail(flags.log_path + ": " + attached.message());
    posed = std::move(*attached);
    for (const io::CarmenLaserScan& s : posed.scans) read_scans.push_back(&s);
    const std::int64_t left_out = posed.scans_outside_odometry + posed.scans_in_gap;
    if (left_out > 0) {
      warnings.Add("scans_without_odometry",
                   flags.log_path + ": front-laser scans without an odometry pose: " +
                       std::to_string(posed.scans_outside_odometry) +
                       " outside the ODOM lines' span, " + std::to_string(posed.scans_in_gap) +
                       " between ODOM lines more than " +
                       core::FormatShortestDouble(odometry_options.max_gap_s) +
                       " s apart (first: line " + std::to_string(posed.first_dropped_line) +
                       "); left out");
    }
    if (posed.odometry_dropped > 0) {
      warnings.Add("odometry_dropped",
                   flags.log_path + ": " + std::to_string(posed.odometry_dropped) +
                       (posed.odometry_dropped == 1 ? " ODOM line" : " ODOM lines") +
                       " stamped no later than the one before; left out");
    }
  } else {
    read_scans = front;
  }
  // The SLAM takes scans in stamp order; a log that wrote some out of order
  // is put in order within a window, and what cannot be is dropped, counted
  // and said.
  const io::CarmenScanOrderOptions order_options;
  core::Result<io::CarmenScanOrder> ordered = io::OrderLaserScans(read_scans, order_options);
  if (!ordered.ok()) return LocalizeFail(flags.log_path + ": " + ordered.message());
  const std::vector<const io::CarmenLaserScan*>& scans = ordered->scans;
  if (ordered->reordered > 0) {
    warnings.Add("scans_reordered", flags.log_path +
                                        ": front-laser scans written after newer ones: " +
                                        std::to_string(ordered->reordered) + " (first: line " +
                                        std::to_string(ordered->first_reordered_line) + ", up to " +
                                        Milliseconds(ordered->max_delay_s) +
                                        " ms late); each was put in its place by its stamp");
  }
  if (ordered->dropped_late + ordered->dropped_duplicate > 0) {
    warnings.Add("scans_dropped", flags.log_path + ": dropped front-laser scans: " +
                                      std::to_string(ordered->dropped_late) + " more than " +
                                      core::FormatShortestDouble(order_options.window_s) +
                                      " s late, " + std::to_string(ordered->dropped_duplicate) +
                                      " with the stamp of the scan before (first: line " +
                                      std::to_string(ordered->first_dropped_line) + ")");
  }
  if (scans.empty()) {
    return LocalizeFail(
        flags.log_path +
        ": no front-laser scan with odometry in the log (FLASER or ROBOTLASER1 lines, or "
        "RAWLASER1 lines between ODOM lines)");
  }
  std::vector<core::Relation> relations;
  if (!flags.relations_path.empty()) {
    core::Result<std::vector<core::Relation>> read = io::ReadRelations(flags.relations_path);
    if (!read.ok()) return LocalizeFail(read.message());
    relations = std::move(*read);
  }

  const lidar::LidarSlamOptions options;
  const lidar::ScanPointsOptions& points_options = options.points;
  lidar::LidarSlam slam(options);
  std::vector<lidar::ScanReport> reports;
  reports.reserve(scans.size());
  const auto slam_start = std::chrono::steady_clock::now();
  int degenerate = 0, matched = 0, loops = 0, loops_rejected_free_space = 0;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const io::CarmenLaserScan& s = *scans[i];
    const core::SE2 T_base_laser = s.robot_pose->Between(*s.laser_pose);
    const lidar::ScanPoints points =
        lidar::ScanPointsFromRanges(s.ranges_m, s.angle_min_rad, s.angle_increment_rad,
                                    s.max_range_m, T_base_laser, points_options);
    core::Result<lidar::ScanReport> report = slam.AddScan(s.stamp_s, *s.robot_pose, points);
    if (!report.ok())
      return LocalizeFail(flags.log_path + " line " + std::to_string(s.line) + ": " +
                          report.message());
    degenerate += report->information.degenerate;
    matched += report->matched;
    loops += report->loops_found;
    loops_rejected_free_space += report->loops_rejected_free_space;
    reports.push_back(std::move(*report));
    if (i % 100 == 0) progress.Update("slam", static_cast<double>(i) / scans.size());
  }
  core::Result<lidar::PoseGraphSummary> final_solve = slam.Finish();
  if (!final_solve.ok()) return LocalizeFail(final_solve.message());
  progress.Update("slam", 1.0);
  const double slam_wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - slam_start).count();
  const core::Trajectory trajectory = slam.Trajectory();

  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(flags.out_dir);
  if (!staged.ok()) return LocalizeFail(staged.message());
  const std::filesystem::path out = staged->path();
  core::Status written = core::WriteTumTrajectory(out / "trajectory.tum", trajectory);
  if (!written.ok()) return LocalizeFail(written.message());
  written = core::WriteFileAtomically(out / "health.jsonl", [&](std::ostream& stream) {
    for (std::size_t i = 0; i < reports.size(); ++i) {
      stream << HealthLine(reports[i], trajectory[i].pose).dump() << "\n";
    }
    return core::Status::Ok();
  });
  if (!written.ok()) return LocalizeFail(written.message());

  const double log_duration_s = scans.back()->stamp_s - scans.front()->stamp_s;
  nlohmann::ordered_json summary;
  summary["log"] = flags.log_path;
  summary["mode"] = "lidar";
  summary["n_scans"] = scans.size();
  summary["n_matched"] = matched;
  summary["n_degenerate"] = degenerate;
  summary["n_nodes"] = slam.graph().num_nodes();
  summary["n_submaps"] = slam.num_submaps();
  summary["n_loops_found"] = loops;
  summary["n_loops_accepted"] = slam.graph().num_loops();
  summary["n_loops_rejected_free_space"] = loops_rejected_free_space;
  summary["n_optimizations"] = slam.num_optimizations();
  summary["log_duration_s"] = log_duration_s;
  summary["lines_skipped"] = read.skipped_line_count;
  summary["scans_reordered"] = ordered->reordered;
  summary["scans_dropped_late"] = ordered->dropped_late;
  summary["scans_dropped_duplicate"] = ordered->dropped_duplicate;
  summary["scans_posed_from_odom"] = posed.attached;
  summary["scans_without_odometry"] = posed.scans_outside_odometry + posed.scans_in_gap;
  summary["odometry_dropped"] = posed.odometry_dropped;
  std::printf(
      "%s: %zu scans over %.1f s, %d matched, %d degenerate, %d nodes, %d submaps, "
      "%d of %d loop closures kept (%d more contradicted free space)\n",
      flags.log_path.c_str(), scans.size(), log_duration_s, matched, degenerate,
      slam.graph().num_nodes(), slam.num_submaps(), slam.graph().num_loops(), loops,
      loops_rejected_free_space);
  if (!relations.empty()) {
    core::Result<core::RelationErrorSummary> errors =
        core::ComputeRelationErrors(trajectory, relations);
    if (!errors.ok())
      return LocalizeFail("evaluating against " + flags.relations_path + ": " + errors.message());
    nlohmann::ordered_json accuracy;
    std::printf("relation errors (%s):\n", flags.relations_path.c_str());
    for (const core::MetricField& f : core::MetricFields(*errors)) {
      accuracy[f.key] = f.value;
      std::printf(f.is_count ? "  %-28s %10.0f\n" : "  %-28s %10.4f\n", f.label.c_str(), f.value);
    }
    std::printf("  translation %.4f +- %.4f m, rotation %.3f +- %.3f deg\n", errors->trans_m.mean,
                errors->trans_m.std_dev, errors->rot_deg.mean, errors->rot_deg.std_dev);
    summary["accuracy"] = accuracy;
    // The front end alone (scan-to-submap matching, no pose graph).
    core::Trajectory local;
    for (const lidar::ScanReport& r : reports) local.push_back({r.stamp_s, r.T_local_base, {}});
    core::Result<core::RelationErrorSummary> local_errors =
        core::ComputeRelationErrors(local, relations);
    if (local_errors.ok()) {
      std::printf("  front end only: translation %.4f +- %.4f m, rotation %.3f +- %.3f deg\n",
                  local_errors->trans_m.mean, local_errors->trans_m.std_dev,
                  local_errors->rot_deg.mean, local_errors->rot_deg.std_dev);
      summary["front_end_rel_trans_mean_m"] = local_errors->trans_m.mean;
      summary["front_end_rel_rot_mean_deg"] = local_errors->rot_deg.mean;
    }
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  summary["wall_s"] = wall_s;
  summary["slam_wall_s"] = slam_wall_s;
  const double cpu_s = ProcessCpuSeconds() - cpu_start;
  summary["cpu_s"] = cpu_s;
  summary["realtime_factor"] = log_duration_s / wall_s;
  // On a shared machine the wall clock waits for other processes too.
  summary["realtime_factor_cpu"] = log_duration_s / cpu_s;
  summary["peak_rss_mb"] = ProcessPeakRssMb();
  summary["warnings"] = warnings.Json();
  written = core::WriteFileAtomically(out / "summary.json", summary.dump(2) + "\n");
  if (!written.ok()) return LocalizeFail(written.message());
  if (core::Status s = staged->Commit(); !s.ok()) return LocalizeFail(s.message());
  std::printf(
      "%.1f s wall (%.0fx real time), %.1f s CPU (%.0fx), peak RSS %.0f MiB; wrote "
      "%s/{trajectory.tum, health.jsonl, summary.json}\n",
      wall_s, log_duration_s / wall_s, cpu_s, log_duration_s / cpu_s, ProcessPeakRssMb(),
      flags.out_dir.c_str());
  return 0;
}

}  // namespace groundline::tools
