#include "groundline/localization/atlas_mapper.h"

#include <ceres/ceres.h>
#include <ceres/covariance.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include "groundline/core/covariance.h"
#include "groundline/core/se2_manifold.h"
#include "groundline/core/trajectory_association.h"
#include "groundline/localization/floor_factors.h"
#include "groundline/localization/landmark_tracker.h"
#include "groundline/localization/lidar/scan_odometry.h"
#include "groundline/localization/relative_pose_factor.h"

namespace groundline::localization {

// One landmark while associating: its estimate fused from the sightings'
// own covariances (the trajectory's error is common to them and is kept out
// of the fusion, so that the gate does not close with their number), and
// the sightings that formed it.
struct AtlasMapper::LineTrack {
  AtlasLine estimate;
  std::vector<std::pair<int, int>> sightings;  // (keyframe, observation)
};
struct AtlasMapper::JunctionTrack {
  AtlasJunction estimate;
  std::vector<std::pair<int, int>> sightings;
};

namespace {

using LineTrack = AtlasMapper::LineTrack;
using JunctionTrack = AtlasMapper::JunctionTrack;

int DistinctKeyframes(const std::vector<std::pair<int, int>>& sightings) {
  int n = 0, last = -1;
  for (const auto& [k, o] : sightings) {
    n += k != last;
    last = k;
  }
  return n;
}

// Two landmarks of one marking: its parts first seen apart (further than the
// extent margin), then grown toward each other by later sightings. Merged
// when their lines agree within the association gate, each estimate taken
// with the trajectory's uncertainty about its middle (LineCovarianceAbout),
// and their extents overlap; junctions when their points agree within it.
void MergeDuplicates(const AtlasMapperOptions& options, std::vector<LineTrack>* lines,
                     std::vector<JunctionTrack>* junctions) {
  // The trajectory's uncertainty of a landmark's line, about its middle.
  const auto pose_part = [&](const AtlasLine& l) -> Eigen::Matrix2d {
    return LineCovarianceAbout(l.line_map, 0.5 * (l.endpoint_a_m + l.endpoint_b_m),
                               options.pose_sigma_m, options.pose_sigma_rad);
  };
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < lines->size(); ++i) {
      for (std::size_t j = i + 1; j < lines->size(); ++j) {
        AtlasLine& a = (*lines)[i].estimate;
        const AtlasLine& b = (*lines)[j].estimate;
        if (!KindsCompatible(b.kind, a.kind) || !KindsCompatible(a.kind, b.kind)) continue;
        if (!ExtentsOverlap(b, a, options.association.extent_margin_m)) continue;
        const Eigen::Vector2d nu = perception::LineDifference(b.line_map, a.line_map);
        const Eigen::Matrix2d b_cov =
            perception::CovarianceInDescriptionOf(b.line_map, a.line_map, b.covariance);
        const Eigen::Matrix2d b_pose =
            perception::CovarianceInDescriptionOf(b.line_map, a.line_map, pose_part(b));
        const Eigen::Matrix2d a_all = a.covariance + pose_part(a);
        const Eigen::Matrix2d joint = a_all + b_cov + b_pose;
        if (core::SquaredMahalanobis<2>(nu, joint) > options.association.gate_chi2) continue;
        Eigen::Vector2d x(a.line_map.rho_m, a.line_map.alpha_rad);
        FuseGaussian2(nu, b_cov, &x, &a.covariance);
        a.line_map = perception::NormalizeLine(x(0), x(1), &a.covariance);
        ExtendLineExtent(b.endpoint_a_m, &a);
        ExtendLineExtent(b.endpoint_b_m, &a);
        auto& sightings = (*lines)[i].sightings;
        sightings.insert(sightings.end(), (*lines)[j].sightings.begin(),
                         (*lines)[j].sightings.end());
        std::sort(sightings.begin(), sightings.end());
        lines->erase(lines->begin() + static_cast<long>(j));
        merged = true;
        --j;
      }
    }
  }
  const double pose_m2 = options.pose_sigma_m * options.pose_sigma_m;
  for (std::size_t i = 0; i < junctions->size(); ++i) {
    for (std::size_t j = i + 1; j < junctions->size(); ++j) {
      AtlasJunction& a = (*junctions)[i].estimate;
      const AtlasJunction& b = (*junctions)[j].estimate;
      const Eigen::Vector2d nu = b.point_m - a.point_m;
      Eigen::Matrix2d joint = a.covariance + b.covariance;
      joint.diagonal().array() += 2.0 * pose_m2;
      if (core::SquaredMahalanobis<2>(nu, joint) > options.association.gate_chi2) continue;
      FuseGaussian2(nu, b.covariance, &a.point_m, &a.covariance);
      auto& sightings = (*junctions)[i].sightings;
      sightings.insert(sightings.end(), (*junctions)[j].sightings.begin(),
                       (*junctions)[j].sightings.end());
      std::sort(sightings.begin(), sightings.end());
      junctions->erase(junctions->begin() + static_cast<long>(j));
      --j;
    }
  }
}

// Solves the problem as it stands. The report keeps the first solve's
// initial cost and the last one's final cost.
core::Status Solve(const AtlasMapperOptions& options, ceres::Problem* problem, bool first,
                   AtlasMapperReport* r) {
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, problem, &summary);
  if (!summary.IsSolutionUsable()) {
    return core::Status::Error("mapping: joint solve failed: " + summary.message);
  }
  if (first) r->initial_cost = summary.initial_cost;
  r->final_cost = summary.final_cost;
  return core::Status::Ok();
}

// The keyframes that saw a landmark: their number and first and last stamps.
template <typename Keyframes>
LandmarkSightings SightingsOf(const std::vector<std::pair<int, int>>& sightings,
                              const Keyframes& keyframes) {
  LandmarkSightings seen;
  seen.keyframes = DistinctKeyframes(sightings);
  seen.first_s = seen.last_s = keyframes[static_cast<std::size_t>(sightings.front().first)].stamp_s;
  for (const auto& [k, o] : sightings) {
    const double t = keyframes[static_cast<std::size_t>(k)].stamp_s;
    seen.first_s = std::min(seen.first_s, t);
    seen.last_s = std::max(seen.last_s, t);
  }
  return seen;
}

}  // namespace

lidar::LidarSlamOptions AtlasMapperOptions::DefaultSlam() {
  lidar::LidarSlamOptions slam = lidar::ScanOdometryOptions::DefaultSlam();
  const lidar::LidarSlamOptions loops;  // lidar_slam.h's loop search
  slam.loop_search_every_n_nodes = loops.loop_search_every_n_nodes;
  slam.retain_finished_submaps = true;
  // Rack aisles repeat every bay (lidar_slam.h, loop_check_aliasing).
  slam.loop_check_aliasing = true;
  slam.loop_search.runner_up_distance_m = 0.5;
  return slam;
}

core::Status AtlasMapperOptions::Validate() const {
  for (const core::Status& s :
       {slam.Validate(), association.Validate(), odometry_noise.Validate()}) {
    if (!s.ok()) return core::Status::Error("AtlasMapperOptions: " + s.message());
  }
  if (!(pose_sigma_m > 0.0 && pose_sigma_rad > 0.0 && motion_floor_sigma_m > 0.0 &&
        motion_floor_sigma_rad > 0.0 && sighting_huber > 0.0)) {
    return core::Status::Error("AtlasMapperOptions: sigmas and the Huber scale must be > 0");
  }
  if (!(anchor_gate_m > 0.0 && anchor_gate_rad > 0.0 && anchor_same_line_m > 0.0)) {
    return core::Status::Error("AtlasMapperOptions: the survey's match gates must be > 0");
  }
  if (!(along_track_sigma_m >= 0.0)) {
    return core::Status::Error("AtlasMapperOptions: along_track_sigma_m must be >= 0");
  }
  if (min_line_sightings < 1 || min_face_sightings < 1 || min_junction_sightings < 1 ||
      max_iterations < 1) {
    return core::Status::Error("AtlasMapperOptions: sighting minimums and iterations must be >= 1");
  }
  return core::Status::Ok();
}

AtlasMapper::AtlasMapper(const AtlasMapperOptions& options)
    : options_(options), slam_(options.slam) {
  assert(options.Validate().ok());
}

void AtlasMapper::SetAnchor(const core::SE2& T_map_base, const core::Matrix3& covariance) {
  anchor_.emplace(T_map_base, covariance);
}

core::Status AtlasMapper::SetSurveyedLandmarks(Atlas survey) {
  if (core::Status s = survey.Validate(); !s.ok()) return s.WithContext("surveyed landmarks");
  survey_ = std::move(survey);
  return core::Status::Ok();
}

core::Status AtlasMapper::AddScan(double stamp_s, const core::SE2& T_odom_base,
                                  const lidar::ScanPoints& scan) {
  core::Result<lidar::ScanReport> report = slam_.AddScan(stamp_s, T_odom_base, scan);
  if (!report.ok()) {
    ++scans_failed_;
    return report.status();
  }
  scan_odometry_.push_back({stamp_s, T_odom_base, std::nullopt});
  return core::Status::Ok();
}

void AtlasMapper::AddKeyframe(double stamp_s, const core::SE2& T_odom_base,
                              const FloorObservations& floor,
                              const std::vector<LineObservation>& faces) {
  Keyframe k{stamp_s, T_odom_base, floor.lines, floor.junctions};
  k.lines.insert(k.lines.end(), faces.begin(), faces.end());
  keyframes_.push_back(std::move(k));
}

void AtlasMapper::Associate(const std::vector<std::array<double, 3>>& poses,
                            std::vector<LineTrack>* line_tracks,
                            std::vector<JunctionTrack>* junction_tracks,
                            AtlasMapperReport* r) const {
  // The trajectory's accuracy (base_link, right perturbation).
  const double m2 = options_.pose_sigma_m * options_.pose_sigma_m;
  const double rad2 = options_.pose_sigma_rad * options_.pose_sigma_rad;
  const core::Matrix3 P = core::Vector3(m2, m2, rad2).asDiagonal();
  const double along2 = options_.along_track_sigma_m * options_.along_track_sigma_m;
  const core::Matrix3 P_along = core::Vector3(along2, m2, rad2).asDiagonal();
  Atlas so_far;  // the tracks' estimates, index for index
  for (int k = 0; k < static_cast<int>(keyframes_.size()); ++k) {
    const Keyframe& kf = keyframes_[static_cast<std::size_t>(k)];
    const core::SE2 T = core::PoseFromAmbient(poses[static_cast<std::size_t>(k)]);
    std::vector<Match> lines = AssociateLines(kf.lines, so_far, T, P, options_.association);
    for (Match& m : lines) {
      const LineObservation& o = kf.lines[static_cast<std::size_t>(m.observation)];
      if (m.landmark >= 0 || m.ambiguous || options_.along_track_sigma_m == 0.0 ||
          core::IsFaceKind(o.kind)) {
        continue;
      }
      const std::vector<Match> wide = AssociateLines({o}, so_far, T, P_along, options_.association);
      if (wide[0].landmark >= 0 && !wide[0].ambiguous) m.landmark = wide[0].landmark;
    }
    for (const Match& m : lines) {
      const LineObservation& o = kf.lines[static_cast<std::size_t>(m.observation)];
      if (m.ambiguous) {
        ++r->sightings_ambiguous;
        continue;
      }
      const AtlasLine seen = LineInMap(o, T, core::Matrix3::Zero());
      if (m.landmark < 0) {
        line_tracks->push_back({seen, {{k, m.observation}}});
        so_far.lines.push_back(seen);
        continue;
      }
      LineTrack& track = (*line_tracks)[static_cast<std::size_t>(m.landmark)];
      AtlasLine& e = track.estimate;
      Eigen::Vector2d x(e.line_map.rho_m, e.line_map.alpha_rad);
      FuseGaussian2(
          perception::LineDifference(seen.line_map, e.line_map),
          perception::CovarianceInDescriptionOf(seen.line_map, e.line_map, seen.covariance), &x,
          &e.covariance);
      e.line_map = perception::NormalizeLine(x(0), x(1), &e.covariance);
      ExtendLineExtent(seen.endpoint_a_m, &e);
      ExtendLineExtent(seen.endpoint_b_m, &e);
      track.sightings.push_back({k, m.observation});
      so_far.lines[static_cast<std::size_t>(m.landmark)] = e;
    }
    const std::vector<Match> junctions =
        AssociateJunctions(kf.junctions, so_far, T, P, options_.association);
    for (const Match& m : junctions) {
      const JunctionObservation& o = kf.junctions[static_cast<std::size_t>(m.observation)];
      if (m.ambiguous) {
        ++r->sightings_ambiguous;
        continue;
      }
      const AtlasJunction seen = JunctionInMap(o, T, core::Matrix3::Zero());
      if (m.landmark < 0) {
        junction_tracks->push_back({seen, {{k, m.observation}}});
        so_far.junctions.push_back(seen);
        continue;
      }
      JunctionTrack& track = (*junction_tracks)[static_cast<std::size_t>(m.landmark)];
      FuseGaussian2(seen.point_m - track.estimate.point_m, seen.covariance, &track.estimate.point_m,
                    &track.estimate.covariance);
      track.sightings.push_back({k, m.observation});
      so_far.junctions[static_cast<std::size_t>(m.landmark)] = track.estimate;
    }
  }
  MergeDuplicates(options_, line_tracks, junction_tracks);
  std::erase_if(*line_tracks, [&](const LineTrack& t) {
    const int need = core::IsFaceKind(t.estimate.kind) ? options_.min_face_sightings
                                                       : options_.min_line_sightings;
    const bool drop = DistinctKeyframes(t.sightings) < need;
    r->landmarks_dropped += drop;
    return drop;
  });
  std::erase_if(*junction_tracks, [&](const JunctionTrack& t) {
    const bool drop = DistinctKeyframes(t.sightings) < options_.min_junction_sightings;
    r->landmarks_dropped += drop;
    return drop;
  });
}

core::Result<std::unique_ptr<ceres::Problem>> AtlasMapper::SolveJointly(
    const std::vector<LineTrack>& line_tracks, const std::vector<JunctionTrack>& junction_tracks,
    std::vector<std::array<double, 3>>* poses_io, std::vector<std::array<double, 2>>* line_io,
    std::vector<std::array<double, 2>>* junction_io, AtlasMapperReport* r) const {
  std::vector<std::array<double, 3>>& poses = *poses_io;
  std::vector<std::array<double, 2>>& line_params = *line_io;
  std::vector<std::array<double, 2>>& junction_params = *junction_io;
  ceres::Problem::Options problem_options;
  auto problem = std::make_unique<ceres::Problem>(problem_options);
  // Owned by the problem (once each).
  auto* manifold = new core::SE2Manifold;
  auto* huber = new ceres::HuberLoss(options_.sighting_huber);
  for (auto& p : poses) problem->AddParameterBlock(p.data(), 3, manifold);
  {
    // The start pose ties the atlas to the map frame: the first keyframe is
    // where the wheel odometry since the start put it, with the start's
    // covariance. Not the graph's pose there: the LiDAR's first matches,
    // against a submap of a scan or two, may turn the whole graph by
    // milliradians, which at 45 m are centimetres.
    core::SE2 T = core::PoseFromAmbient(poses[0]);
    // Without a start pose the first keyframe is held where the graph put
    // it; loosely (1 m, 0.1 rad) when surveyed landmarks will place the atlas.
    Eigen::Matrix3d S = HasSurvey() ? core::Vector3(1.0, 1.0, 10.0).asDiagonal()
                                    : core::Vector3(1e4, 1e4, 1e5).asDiagonal();
    if (anchor_) {
      T = keyframes_[0].T_odom_base;
      core::Result<Eigen::Matrix3d> from_start = SqrtInformationFromCovariance(anchor_->second);
      if (!from_start.ok())
        return core::Status::Error("mapping: start pose: " + from_start.message());
      S = *from_start;
    }
    problem->AddResidualBlock(new PosePriorFactor(T, S), nullptr, poses[0].data());
  }
  const double floor_m2 = options_.motion_floor_sigma_m * options_.motion_floor_sigma_m;
  const double floor_rad2 = options_.motion_floor_sigma_rad * options_.motion_floor_sigma_rad;
  for (std::size_t k = 1; k < poses.size(); ++k) {
    const core::SE2 wheels = keyframes_[k - 1].T_odom_base.Between(keyframes_[k].T_odom_base);
    const core::Matrix3 covariance =
        IncrementCovariance(options_.odometry_noise, wheels.translation().norm(), wheels.yaw()) +
        core::Vector3(floor_m2, floor_m2, floor_rad2).asDiagonal().toDenseMatrix();
    core::Result<Eigen::Matrix3d> S = SqrtInformationFromCovariance(covariance);
    if (!S.ok()) return core::Status::Error("mapping: keyframe motion: " + S.message());
    problem->AddResidualBlock(new RelativePoseFactor(wheels, *S), nullptr, poses[k - 1].data(),
                              poses[k].data());
  }
  line_params.clear();
  junction_params.clear();
  line_params.reserve(line_tracks.size());
  junction_params.reserve(junction_tracks.size());
  for (const LineTrack& t : line_tracks) {
    line_params.push_back({t.estimate.line_map.rho_m, t.estimate.line_map.alpha_rad});
    for (const auto& [k, o] : t.sightings) {
      const LineObservation& seen =
          keyframes_[static_cast<std::size_t>(k)].lines[static_cast<std::size_t>(o)];
      core::Result<Eigen::Matrix2d> S = SqrtInformationFromCovariance2(seen.covariance);
      if (!S.ok()) continue;
      problem->AddResidualBlock(new GroundLineFactor(seen.line_base, *S), huber,
                                poses[static_cast<std::size_t>(k)].data(),
                                line_params.back().data());
      ++r->sightings;
    }
  }
  for (const JunctionTrack& t : junction_tracks) {
    junction_params.push_back({t.estimate.point_m.x(), t.estimate.point_m.y()});
    for (const auto& [k, o] : t.sightings) {
      const JunctionObservation& seen =
          keyframes_[static_cast<std::size_t>(k)].junctions[static_cast<std::size_t>(o)];
      core::Result<Eigen::Matrix2d> S = SqrtInformationFromCovariance2(seen.covariance);
      if (!S.ok()) continue;
      problem->AddResidualBlock(new JunctionFactor(seen.point_base_m, *S), huber,
                                poses[static_cast<std::size_t>(k)].data(),
                                junction_params.back().data());
      ++r->sightings;
    }
  }
  if (core::Status s = Solve(options_, problem.get(), /*first=*/true, r); !s.ok()) return s;
  return problem;
}

core::Status AtlasMapper::AnchorToSurvey(const std::vector<LineTrack>& line_tracks,
                                         std::vector<std::array<double, 2>>* line_params,
                                         std::vector<std::array<double, 2>>* junction_params,
                                         double* site_origin, ceres::Problem* problem,
                                         AtlasMapperReport* r) const {
  // The priors are GroundLineFactor / JunctionFactor seen from the survey's
  // origin: a surveyed line is a sighting from the identity pose.
  problem->AddParameterBlock(site_origin, 3);
  problem->SetParameterBlockConstant(site_origin);
  auto* huber = new ceres::HuberLoss(options_.sighting_huber);  // owned by the problem
  bool huber_used = false;
  // The built lines as the first solve left them.
  std::vector<perception::HesseLine> built_lines;
  built_lines.reserve(line_params->size());
  for (const auto& p : *line_params) built_lines.push_back(perception::NormalizeLine(p[0], p[1]));
  for (const AtlasLine& surveyed : survey_.lines) {
    ++r->surveyed;
    const Eigen::Vector2d middle = 0.5 * (surveyed.endpoint_a_m + surveyed.endpoint_b_m);
    std::vector<std::pair<double, std::size_t>> candidates;  // (|offset| at the middle, track)
    for (std::size_t i = 0; i < line_tracks.size(); ++i) {
      AtlasLine built = line_tracks[i].estimate;
      if (!KindsCompatible(built.kind, surveyed.kind)) continue;
      built.line_map = built_lines[i];
      if (!ExtentsOverlap(built, surveyed, options_.anchor_gate_m)) continue;
      const Eigen::Vector2d d = perception::LineDifference(built.line_map, surveyed.line_map);
      const double offset = std::abs(perception::SignedDistance(built.line_map, middle));
      if (std::abs(d(1)) > options_.anchor_gate_rad || offset > options_.anchor_gate_m) continue;
      candidates.emplace_back(offset, i);
    }
    if (candidates.empty()) continue;
    std::sort(candidates.begin(), candidates.end());
    const perception::HesseLine& nearest = built_lines[candidates[0].second];
    const Eigen::Vector2d foot =
        middle - perception::SignedDistance(nearest, middle) * nearest.Normal();
    const bool ambiguous = std::any_of(candidates.begin(), candidates.end(), [&](const auto& c) {
      return std::abs(perception::SignedDistance(built_lines[c.second], foot)) >
             options_.anchor_same_line_m;
    });
    if (ambiguous) {
      ++r->surveyed_ambiguous;
      continue;
    }
    core::Result<Eigen::Matrix2d> S = SqrtInformationFromCovariance2(surveyed.covariance);
    if (!S.ok()) {
      return core::Status::Error("mapping: surveyed line " + std::to_string(surveyed.id) + ": " +
                                 S.message());
    }
    for (const auto& [offset, i] : candidates) {
      problem->AddResidualBlock(new GroundLineFactor(surveyed.line_map, *S), huber, site_origin,
                                (*line_params)[i].data());
    }
    huber_used = true;
    ++r->surveyed_matched;
  }
  for (const AtlasJunction& surveyed : survey_.junctions) {
    ++r->surveyed;
    const auto point = [&](std::size_t i) {
      return Eigen::Vector2d((*junction_params)[i][0], (*junction_params)[i][1]);
    };
    std::vector<std::pair<double, std::size_t>> candidates;
    for (std::size_t i = 0; i < junction_params->size(); ++i) {
      const double distance = (point(i) - surveyed.point_m).norm();
      if (distance <= options_.anchor_gate_m) candidates.emplace_back(distance, i);
    }
    if (candidates.empty()) continue;
    std::sort(candidates.begin(), candidates.end());
    // Built junctions within anchor_same_line_m of the nearest are one
    // junction seen twice; any other within the gate: ambiguous.
    const bool ambiguous = std::any_of(candidates.begin(), candidates.end(), [&](const auto& c) {
      return (point(c.second) - point(candidates[0].second)).norm() > options_.anchor_same_line_m;
    });
    if (ambiguous) {
      ++r->surveyed_ambiguous;
      continue;
    }
    core::Result<Eigen::Matrix2d> S = SqrtInformationFromCovariance2(surveyed.covariance);
    if (!S.ok()) {
      return core::Status::Error("mapping: surveyed junction " + std::to_string(surveyed.id) +
                                 ": " + S.message());
    }
    for (const auto& [distance, i] : candidates) {
      problem->AddResidualBlock(new JunctionFactor(surveyed.point_m, *S), huber, site_origin,
                                (*junction_params)[i].data());
    }
    huber_used = true;
    ++r->surveyed_matched;
  }
  if (!huber_used) {
    delete huber;
    return core::Status::Ok();
  }
  return Solve(options_, problem, /*first=*/false, r);
}

core::Result<Atlas> AtlasMapper::Build(AtlasMapperReport* report) {
  AtlasMapperReport r;
  if (keyframes_.empty()) return core::Status::Error("mapping: no keyframe to build an atlas from");
  r.keyframes = static_cast<int>(keyframes_.size());
  r.scans = static_cast<int>(scan_odometry_.size());
  r.scans_failed = scans_failed_;

  // 1. The graph's correction of the odometry, per scan: the SLAM's map
  // frame is the base at the first scan, whose odometry pose is its place
  // in the map frame of the start pose.
  core::Trajectory corrections;
  if (!scan_odometry_.empty()) {
    core::Result<lidar::PoseGraphSummary> solved = slam_.Finish();
    if (!solved.ok()) return core::Status::Error("mapping: pose graph: " + solved.message());
    r.loops = slam_.graph().num_loops(true);
    r.loops_rejected = slam_.graph().num_loops(false) - r.loops;
    const core::Trajectory slam = slam_.Trajectory();
    const core::SE2 T_map_slam = scan_odometry_.front().pose;
    corrections.reserve(slam.size());
    for (std::size_t i = 0; i < slam.size(); ++i) {
      corrections.push_back({slam[i].stamp_s,
                             T_map_slam * slam[i].pose * scan_odometry_[i].pose.Inverse(),
                             std::nullopt});
    }
  }
  std::vector<std::array<double, 3>> poses;
  poses.reserve(keyframes_.size());
  lidar_trajectory_.clear();
  for (const Keyframe& k : keyframes_) {
    const core::SE2 C =
        corrections.empty() ? core::SE2() : core::InterpolatePose(corrections, k.stamp_s);
    poses.push_back(core::AmbientOf(C * k.T_odom_base));
    lidar_trajectory_.push_back({k.stamp_s, C * k.T_odom_base, std::nullopt});
  }

  // 2-3. Association, then the joint solve.
  std::vector<LineTrack> line_tracks;
  std::vector<JunctionTrack> junction_tracks;
  std::vector<std::array<double, 2>> line_params, junction_params;
  std::array<double, 3> site_origin{0.0, 0.0, 0.0};  // outlives the problem
  Associate(poses, &line_tracks, &junction_tracks, &r);
  core::Result<std::unique_ptr<ceres::Problem>> solved =
      SolveJointly(line_tracks, junction_tracks, &poses, &line_params, &junction_params, &r);
  if (!solved.ok()) return solved.status();
  const std::unique_ptr<ceres::Problem> problem = std::move(solved).value();
  if (HasSurvey()) {
    if (core::Status s = AnchorToSurvey(line_tracks, &line_params, &junction_params,
                                        site_origin.data(), problem.get(), &r);
        !s.ok()) {
      return s;
    }
  }

  // 4. Marginal covariances of the landmarks.
  std::vector<std::pair<const double*, const double*>> blocks;
  for (const auto& p : line_params) blocks.emplace_back(p.data(), p.data());
  for (const auto& p : junction_params) blocks.emplace_back(p.data(), p.data());
  ceres::Covariance::Options covariance_options;
  covariance_options.num_threads = 1;
  ceres::Covariance covariance(covariance_options);
  r.covariances = covariance.Compute(blocks, problem.get());

  Atlas atlas;
  // The marginals are the landmarks' accuracy, the trajectory's included.
  atlas.covariances_stated = r.covariances;
  std::int64_t id = 0;
  for (std::size_t i = 0; i < line_tracks.size(); ++i) {
    const LineTrack& t = line_tracks[i];
    AtlasLine line;
    line.id = ++id;
    line.kind = t.estimate.kind;
    Eigen::Matrix2d cov = t.estimate.covariance;
    if (r.covariances)
      covariance.GetCovarianceBlock(line_params[i].data(), line_params[i].data(), cov.data());
    line.line_map = perception::NormalizeLine(line_params[i][0], line_params[i][1], &cov);
    line.covariance = 0.5 * (cov + cov.transpose());
    line.seen = SightingsOf(t.sightings, keyframes_);
    // The extent: every sighting's ends, projected onto the solved line.
    bool first = true;
    for (const auto& [k, o] : t.sightings) {
      const LineObservation& seen =
          keyframes_[static_cast<std::size_t>(k)].lines[static_cast<std::size_t>(o)];
      const core::SE2 T = core::PoseFromAmbient(poses[static_cast<std::size_t>(k)]);
      for (const Eigen::Vector2d& end : {T * seen.endpoint_a_base_m, T * seen.endpoint_b_base_m}) {
        if (first) {
          const Eigen::Vector2d on =
              end - perception::SignedDistance(line.line_map, end) * line.line_map.Normal();
          line.endpoint_a_m = line.endpoint_b_m = on;
          first = false;
        } else {
          ExtendLineExtent(end, &line);
        }
      }
    }
    (core::IsFaceKind(line.kind) ? r.faces : r.lines) += 1;
    atlas.lines.push_back(line);
  }
  id = 0;
  for (std::size_t i = 0; i < junction_tracks.size(); ++i) {
    AtlasJunction j;
    j.id = ++id;
    j.point_m = Eigen::Vector2d(junction_params[i][0], junction_params[i][1]);
    j.covariance = junction_tracks[i].estimate.covariance;
    if (r.covariances) {
      covariance.GetCovarianceBlock(junction_params[i].data(), junction_params[i].data(),
                                    j.covariance.data());
    }
    j.covariance = 0.5 * (j.covariance + j.covariance.transpose());
    j.seen = SightingsOf(junction_tracks[i].sightings, keyframes_);
    atlas.junctions.push_back(j);
  }
  r.junctions = static_cast<int>(atlas.junctions.size());
  keyframe_trajectory_.clear();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    keyframe_trajectory_.push_back(
        {keyframes_[k].stamp_s, core::PoseFromAmbient(poses[k]), std::nullopt});
  }
  if (core::Status s = atlas.Validate(); !s.ok()) {
    return core::Status::Error("mapping: the atlas built is invalid: " + s.message());
  }
  if (report != nullptr) *report = r;
  return atlas;
}

}  // namespace groundline::localization
