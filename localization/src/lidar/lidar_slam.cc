#include "groundline/localization/lidar/lidar_slam.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

#include "groundline/localization/relative_pose_factor.h"

namespace groundline::localization::lidar {
namespace {

std::vector<core::Vector2> PositionsOf(const ScanPoints& scan) {
  std::vector<core::Vector2> out;
  out.reserve(scan.points.size());
  for (const ScanPoint& p : scan.points) out.push_back(p.point_m);
  return out;
}

// The node's pose in the submap that it starts is exact by construction.
const core::Matrix3 kSubmapOriginSqrtInformation = core::Matrix3::Identity() * 100.0;

}  // namespace

core::Status LidarSlamOptions::Validate() const {
  for (const core::Status& s :
       {points.Validate(), grid.Validate(), matcher.Validate(), information.Validate(),
        loop_search.Validate(), graph.Validate(), odometry_noise.Validate(),
        loop_free_space.Validate(), loop_aliasing.Validate()}) {
    if (!s.ok()) return s;
  }
  if (scans_per_submap < 2) return core::Status::Error("scans_per_submap must be >= 2");
  if (!(keyframe_distance_m >= 0.0 && keyframe_angle_rad >= 0.0 && keyframe_time_s > 0.0)) {
    return core::Status::Error("keyframe thresholds must be >= 0 (time > 0)");
  }
  if (!(min_match_score >= 0.0 && min_match_score < 1.0 && loop_min_score > 0.0 &&
        loop_min_score < 1.0)) {
    return core::Status::Error("scores must be in [0, 1)");
  }
  if (!(loop_ambiguity_max_angle_rad >= 0.0 &&
        loop_ambiguity_max_angle_rad <= 1.5707963267948966)) {
    return core::Status::Error("loop_ambiguity_max_angle_rad must be in [0, pi/2]");
  }
  if (!(max_match_correction_m > 0.0 && max_match_correction_rad > 0.0)) {
    return core::Status::Error("max_match_correction_m and max_match_correction_rad must be > 0");
  }
  if (match_correction_persist_scans < 1) {
    return core::Status::Error("match_correction_persist_scans must be >= 1");
  }
  if (loop_search_every_n_nodes < 1 || optimize_every_n_nodes < 1 || precomputed_cache_size < 1) {
    return core::Status::Error("loop/optimize periods and cache size must be >= 1");
  }
  return core::Status::Ok();
}

LidarSlam::LidarSlam(const LidarSlamOptions& options)
    : options_(options),
      submaps_(options.grid, options.scans_per_submap, options.retain_finished_submaps),
      graph_(options.graph) {
  assert(options.Validate().ok());
}

core::Result<ScanReport> LidarSlam::AddScan(double stamp_s, const core::SE2& T_odom_base,
                                            const ScanPoints& scan) {
  if (!scans_.empty() && !(stamp_s > scans_.back().stamp_s)) {
    return core::Status::Error("LiDAR scan at " + std::to_string(stamp_s) +
                               " s is not after the previous one at " +
                               std::to_string(scans_.back().stamp_s) + " s");
  }
  ScanReport report;
  report.stamp_s = stamp_s;
  report.T_local_base =
      scans_.empty() ? core::SE2() : last_local_ * last_odom_.Between(T_odom_base);
  const core::SE2 odometry_prediction = report.T_local_base;
  report.information = ComputeMatchInformation(scan.points, options_.information);
  const std::shared_ptr<const Submap> submap = submaps_.matching_submap();
  if (submap != nullptr && !scan.points.empty()) {
    const std::vector<core::Vector2> points = PositionsOf(scan);
    // Odometry in logs can be stale for a while and then jump: the motion
    // of the last scan interval, continued, is the second hypothesis.
    std::vector<core::SE2> predictions = {report.T_local_base};
    if (scans_.size() >= 2) {
      const ScanRecord& a = scans_[scans_.size() - 2];
      const ScanRecord& b = scans_.back();
      const double ratio = (stamp_s - b.stamp_s) / (b.stamp_s - a.stamp_s);
      const core::SE2 velocity =
          b.T_local_base * core::SE2::Exp(ratio * a.T_local_base.Between(b.T_local_base).Log());
      if (!velocity.IsApprox(report.T_local_base, options_.hypothesis_distance_m,
                             options_.hypothesis_angle_rad)) {
        predictions.push_back(velocity);
      }
    }
    double best_score = -1.0;
    core::SE2 prediction, initial;
    for (std::size_t h = 0; h < predictions.size(); ++h) {
      double score = 0.0;
      const core::SE2 T_submap_predicted = submap->T_local_submap.Between(predictions[h]);
      const core::SE2 found =
          CorrelativeSearch(submap->grid, points, T_submap_predicted, options_.matcher, &score);
      const double gain = h == 0 ? 0.0 : options_.hypothesis_min_gain;
      if (score > best_score + gain) {
        best_score = score, prediction = T_submap_predicted, initial = found;
        report.velocity_prediction = h > 0;
      }
    }
    core::Result<ScanMatchResult> match =
        MatchScan(submap->grid, points, prediction, options_.matcher, initial);
    if (!match.ok() || match->score < options_.min_match_score) {
      const PrecomputedGrids grids(submap->grid, options_.recovery_search.depth);
      const std::optional<BranchAndBoundMatch> coarse =
          BranchAndBoundSearch(submap->grid, grids, points, prediction, options_.min_match_score,
                               options_.recovery_search);
      if (coarse) {
        match = MatchScan(submap->grid, points, coarse->T_grid_base, options_.matcher,
                          coarse->T_grid_base);
      }
    }
    if (match.ok()) {
      report.match = *match;
      if (match->score >= options_.min_match_score) {
        report.matched = true;
        core::SE2 T_submap_base = match->T_grid_base;
        if (report.information.degenerate) {
          // The scan does not see along its weakest direction: keep the
          // prediction's component there (right perturbation, base frame).
          const core::Vector3 v = report.information.weakest_direction;
          const core::Vector3 delta = T_submap_base.Minus(prediction);
          T_submap_base = prediction.Plus(delta - v.dot(delta) * v);
        }
        const core::SE2 T_local_matched = submap->T_local_submap * T_submap_base;
        const core::SE2 correction = odometry_prediction.Between(T_local_matched);
        auto beyond = [this](const core::SE2& c) {
          return c.translation().norm() > options_.max_match_correction_m ||
                 std::abs(c.yaw()) > options_.max_match_correction_rad;
        };
        bool use = true;
        if (beyond(correction)) {
          const bool repeated = gated_streak_ > 0 && !beyond(gated_correction_.Between(correction));
          gated_streak_ = repeated ? gated_streak_ + 1 : 1;
          gated_correction_ = correction;
          use = gated_streak_ >= options_.match_correction_persist_scans;
        }
        if (use) {
          gated_streak_ = 0;
          report.T_local_base = T_local_matched;
        } else {
          report.matched = false;
          report.match_gated = true;
        }
      }
    }
  }
  const bool first = node_local_.empty();
  if (!first) {
    const core::SE2 moved = node_local_.back().Between(report.T_local_base);
    report.keyframe = moved.translation().norm() >= options_.keyframe_distance_m ||
                      std::abs(moved.yaw()) >= options_.keyframe_angle_rad ||
                      stamp_s - node_stamp_s_.back() >= options_.keyframe_time_s;
  }
  report.keyframe = report.keyframe || first;
  last_odom_ = T_odom_base;
  last_local_ = report.T_local_base;
  if (report.keyframe) {
    node_stamp_s_.push_back(stamp_s);
    AddKeyframe(T_odom_base, scan, &report);
    if (loops_since_optimization_ > 0 &&
        nodes_since_optimization_ >= options_.optimize_every_n_nodes) {
      core::Result<PoseGraphSummary> solved = graph_.Optimize();
      if (!solved.ok()) return solved.status();
      ++num_optimizations_;
      loops_since_optimization_ = 0;
      nodes_since_optimization_ = 0;
    }
  }
  scans_.push_back({stamp_s, report.T_local_base, graph_.num_nodes() - 1});
  return report;
}

void LidarSlam::AddKeyframe(const core::SE2& T_odom_base, const ScanPoints& scan,
                            ScanReport* report) {
  const core::SE2& T_local = report->T_local_base;
  core::SE2 T_map = T_local;
  if (!node_local_.empty()) {
    const int prev = graph_.num_nodes() - 1;
    T_map = graph_.node(prev) * node_local_.back().Between(T_local);
  }
  const int node = graph_.AddNode(T_map);
  report->node = node;
  if (node > 0) {
    // The front end's motion since the previous keyframe (odometry fused
    // with the scan match): information = odometry's + the match's.
    const core::SE2 motion = node_local_.back().Between(T_local);
    core::Matrix3 information = MotionCovariance(motion).inverse();
    if (report->matched) {
      const core::Matrix3& S = report->information.sqrt_information;
      information += S.transpose() * S;
    }
    const Eigen::LLT<core::Matrix3> llt(information);
    assert(llt.info() == Eigen::Success);
    graph_.AddConstraint(
        {ConstraintKind::kOdometry, node - 1, node, motion, llt.matrixU().toDenseMatrix()});
  }
  node_local_.push_back(T_local);
  node_odom_.push_back(T_odom_base);
  const std::size_t submaps_before = submaps_.all().size();
  std::vector<std::shared_ptr<Submap>> finished;
  const std::vector<int> ids = submaps_.InsertScan(T_local, scan, &finished);
  for (std::size_t s = submaps_before; s < submaps_.all().size(); ++s) {
    graph_.AddSubmap(T_map * T_local.Between(submaps_.all()[s]->T_local_submap));
  }
  for (int id : ids) {
    const core::SE2 T_submap_node = submaps_.all()[id]->T_local_submap.Between(T_local);
    const bool origin = T_submap_node.IsApprox(core::SE2(), 1e-9, 1e-9);
    if (!origin && !(report->matched && report->information.rank > 0)) continue;
    graph_.AddConstraint(
        {ConstraintKind::kIntraSubmap, id, node, T_submap_node,
         origin ? kSubmapOriginSqrtInformation : report->information.sqrt_information});
  }
  node_submaps_.push_back(ids);
  ++nodes_since_optimization_;
  if (node % options_.loop_search_every_n_nodes == 0) {
    SearchLoops(node, scan, report);
    loops_since_optimization_ += report->loops_found;
  }
}

core::Matrix3 LidarSlam::MotionCovariance(const core::SE2& motion) const {
  const double floor_m2 = options_.motion_floor_sigma_m * options_.motion_floor_sigma_m;
  const double floor_rad2 = options_.motion_floor_sigma_rad * options_.motion_floor_sigma_rad;
  return IncrementCovariance(options_.odometry_noise, motion.translation().norm(), motion.yaw()) +
         core::Vector3(floor_m2, floor_m2, floor_rad2).asDiagonal().toDenseMatrix();
}

const PrecomputedGrids& LidarSlam::Precomputed(const Submap& submap) {
  auto it = precomputed_.find(submap.id);
  if (it != precomputed_.end()) {
    precomputed_lru_.remove(submap.id);
    precomputed_lru_.push_front(submap.id);
    return *it->second;
  }
  if (static_cast<int>(precomputed_.size()) >= options_.precomputed_cache_size) {
    precomputed_.erase(precomputed_lru_.back());
    precomputed_lru_.pop_back();
  }
  precomputed_lru_.push_front(submap.id);
  auto grids = std::make_unique<PrecomputedGrids>(submap.grid, options_.loop_search.depth);
  return *precomputed_.emplace(submap.id, std::move(grids)).first->second;
}

void LidarSlam::SearchLoops(int node, const ScanPoints& scan, ScanReport* report) {
  if (scan.points.empty()) return;
  const std::vector<core::Vector2> points = PositionsOf(scan);
  const MatchInformation information = ComputeMatchInformation(scan.points, options_.information);
  if (information.rank == 0) return;
  core::Matrix3 sqrt_information = information.sqrt_information;
  if (options_.loop_check_aliasing) {
    const ScanAliasing aliasing = DetectScanAliasing(scan, information, options_.loop_aliasing);
    if (aliasing.aliased) {
      sqrt_information = RemoveTranslation(sqrt_information, aliasing.direction);
      report->loop_scan_aliased = true;
    }
  }
  const core::Vector2 weakest = WeakestTranslation(information);
  const std::vector<int>& own = node_submaps_[static_cast<std::size_t>(node)];
  for (const std::shared_ptr<Submap>& submap : submaps_.all()) {
    if (submap == nullptr || !submap->finished) continue;  // released, or still active
    if (std::find(own.begin(), own.end(), submap->id) != own.end()) continue;
    const core::SE2 estimate = graph_.submap(submap->id).Between(graph_.node(node));
    if (!submap->grid.IsKnown(submap->grid.CellOf(estimate.translation()))) continue;
    const std::optional<BranchAndBoundMatch> coarse =
        BranchAndBoundSearch(submap->grid, Precomputed(*submap), points, estimate,
                             options_.loop_min_score, options_.loop_search);
    if (!coarse) continue;
    core::Result<ScanMatchResult> refined =
        MatchScan(submap->grid, points, coarse->T_grid_base, options_.matcher, coarse->T_grid_base);
    if (!refined.ok() || refined->score < options_.loop_min_score) continue;
    core::Matrix3 loop_sqrt_information = sqrt_information;
    if (coarse->runner_up) {
      // The line between the two candidates, in the base frame.
      const core::Vector2 between =
          coarse->T_grid_base.Rotation().transpose() *
          (coarse->runner_up->T_grid_base.translation() - coarse->T_grid_base.translation());
      const core::Vector2 d = between.normalized();
      if (std::abs(d.dot(weakest)) < std::cos(options_.loop_ambiguity_max_angle_rad)) {
        ++report->loops_rejected_ambiguous;
        continue;
      }
      loop_sqrt_information = RemoveTranslation(loop_sqrt_information, d);
    }
    const FreeSpaceCheck free_space =
        CheckFreeSpace(submap->grid, scan, refined->T_grid_base, options_.loop_free_space);
    if (!free_space.consistent) {
      ++report->loops_rejected_free_space;
      continue;
    }
    graph_.AddConstraint(
        {ConstraintKind::kLoop, submap->id, node, refined->T_grid_base, loop_sqrt_information});
    ++report->loops_found;
    if (coarse->runner_up) ++report->loops_ambiguous;
  }
}

core::Result<PoseGraphSummary> LidarSlam::Finish() {
  core::Result<PoseGraphSummary> solved = graph_.Optimize();
  if (solved.ok()) ++num_optimizations_;
  return solved;
}

core::Trajectory LidarSlam::Trajectory() const {
  core::Trajectory out;
  out.reserve(scans_.size());
  // The graph's correction of the local frame at node n.
  auto correction = [this](int n) {
    return graph_.node(n) * node_local_[static_cast<std::size_t>(n)].Inverse();
  };
  for (const ScanRecord& s : scans_) {
    core::SE2 T_map_local = correction(s.node);
    const int next = s.node + 1;
    if (options_.interpolate_corrections && next < graph_.num_nodes()) {
      // Between two keyframes, the correction moves from one node's to the
      // next's (linear in time), so that the trajectory does not jump at
      // the next keyframe.
      const double t0 = node_stamp_s_[static_cast<std::size_t>(s.node)];
      const double t1 = node_stamp_s_[static_cast<std::size_t>(next)];
      const double alpha = std::clamp((s.stamp_s - t0) / (t1 - t0), 0.0, 1.0);
      T_map_local =
          T_map_local * core::SE2::Exp(alpha * T_map_local.Between(correction(next)).Log());
    }
    out.push_back({s.stamp_s, T_map_local * s.T_local_base, std::nullopt});
  }
  return out;
}

}  // namespace groundline::localization::lidar
