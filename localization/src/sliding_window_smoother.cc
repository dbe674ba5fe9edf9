#include "groundline/localization/sliding_window_smoother.h"

#include <ceres/loss_function.h>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>

#include "groundline/core/covariance.h"
#include "groundline/core/run_timing.h"
#include "groundline/core/se2_manifold.h"
#include "groundline/core/text_parse.h"
#include "groundline/localization/floor_factors.h"
#include "groundline/localization/relative_pose_factor.h"

namespace groundline::localization {
namespace {

using Clock = std::chrono::steady_clock;

using core::SecondsSince;

core::Matrix3 OdometryCovarianceFloor(const SmootherOptions& options) {
  const double m2 = options.odometry_sigma_floor_m * options.odometry_sigma_floor_m;
  const double rad2 = options.odometry_sigma_floor_rad * options.odometry_sigma_floor_rad;
  return core::Vector3(m2, m2, rad2).asDiagonal();
}

// The number of directions a square-root information constrains.
int MeasurementRank(const core::Matrix3& sqrt_information) {
  const Eigen::JacobiSVD<core::Matrix3> svd(sqrt_information);
  const double largest = svd.singularValues()(0);
  int rank = 0;
  for (int k = 0; k < 3; ++k) rank += largest > 0.0 && svd.singularValues()(k) > 1e-9 * largest;
  return rank;
}

}  // namespace

core::Status SmootherOptions::Validate() const {
  if (!(window_s > 0.0)) return core::Status::Error("smoother window_s must be > 0");
  if (!(line_loss_scale > 0.0)) return core::Status::Error("smoother line_loss_scale must be > 0");
  if (!(junction_loss_scale > 0.0)) {
    return core::Status::Error("smoother junction_loss_scale must be > 0");
  }
  if (max_iterations < 1) return core::Status::Error("smoother max_iterations must be >= 1");
  if (!(step_tolerance > 0.0)) return core::Status::Error("smoother step_tolerance must be > 0");
  if (!(ceres_tolerance > 0.0)) return core::Status::Error("smoother ceres_tolerance must be > 0");
  if (!(odometry_sigma_floor_m > 0.0) || !(odometry_sigma_floor_rad > 0.0)) {
    return core::Status::Error("smoother odometry_sigma_floor_m and _rad must be > 0");
  }
  if (!(slip_sigma_m >= 0.0) || !(track_m > 0.0) || slip_min_matches < 1 ||
      !(slip_relative_chi2 >= 0.0) || !(slip_residual_chi2 >= 0.0)) {
    return core::Status::Error(
        "smoother slip_sigma_m must be >= 0, track_m > 0, slip_min_matches >= 1, "
        "slip_relative_chi2 >= 0 and slip_residual_chi2 >= 0");
  }
  if (tracker.min_keyframes < 1) {
    return core::Status::Error("smoother tracker.min_keyframes must be >= 1");
  }
  if (core::Status s = upkeep.Validate(); !s.ok()) return s;
  return association.Validate();
}

core::Status AtlasUpkeepOptions::Validate() const {
  if (tracker.min_keyframes < 1 || tracker.max_gap_keyframes < 1) {
    return core::Status::Error(
        "smoother upkeep.tracker.min_keyframes and max_gap_keyframes must be >= 1");
  }
  if (retire_after_misses < 1) {
    return core::Status::Error("smoother upkeep.retire_after_misses must be >= 1");
  }
  if (!(view_margin_m >= 0.0) || !(min_in_view_m > 0.0)) {
    return core::Status::Error(
        "smoother upkeep.view_margin_m must be >= 0 and upkeep.min_in_view_m > 0");
  }
  if (birth_min_matches < 0 || !(birth_max_position_sigma_m > 0.0)) {
    return core::Status::Error(
        "smoother upkeep.birth_min_matches must be >= 0 and upkeep.birth_max_position_sigma_m "
        "> 0");
  }
  if (!(birth_novelty_chi2 >= 0.0)) {
    return core::Status::Error("smoother upkeep.birth_novelty_chi2 must be >= 0, got " +
                               core::FormatShortestDouble(birth_novelty_chi2));
  }
  return core::Status::Ok();
}

PoseEstimate PropagateFromKeyframe(const PoseEstimate& keyframe, const RelativeMotion& motion,
                                   double stamp_s) {
  PoseEstimate out;
  out.stamp_s = stamp_s;
  out.T_map_base = keyframe.T_map_base * motion.T_start_end;
  const core::Matrix3 A = motion.T_start_end.Inverse().Adjoint();
  out.covariance = A * keyframe.covariance * A.transpose() + motion.covariance;
  return out;
}

core::Matrix3 SlipCovariance(const RelativeMotion& motion, double slip_sigma_m, double track_m) {
  const double v = slip_sigma_m * slip_sigma_m;
  const core::Matrix3 at_start = core::Vector3(0.25 * v, 0.0, v / (track_m * track_m)).asDiagonal();
  const core::Matrix3 A = motion.T_start_end.Inverse().Adjoint();
  return A * at_start * A.transpose();
}

double OneWheelSlipResidualChi2(const RelativeMotion& motion, const core::Vector3& r,
                                const core::Matrix3& W, double track_m, double max_slip_margin_m) {
  const core::Vector3 xi = motion.T_start_end.Log();
  const double max_slip_m =
      xi.head<2>().norm() + std::abs(xi(2)) * 0.5 * track_m + max_slip_margin_m;
  // The slip's direction in the motion's end frame when it happened at the
  // start (transported by the motion), half way, or at the end.
  const core::SE2 half = core::SE2::Exp(0.5 * motion.T_start_end.Log());
  const std::array<core::Matrix3, 3> transports = {
      motion.T_start_end.Inverse().Adjoint(),
      (half.Inverse() * motion.T_start_end).Inverse().Adjoint(), core::Matrix3::Identity()};
  const double chi2 = r.dot(W * r);
  double best = chi2;
  for (const core::Matrix3& A : transports) {
    for (const double side : {1.0, -1.0}) {
      const core::Vector3 d = A * core::Vector3(0.5, 0.0, side / track_m);
      const double dWd = d.dot(W * d);
      if (!(dWd > 0.0)) continue;
      // r^T W r - 2 s d^T W r + s^2 d^T W d at the best slip s within the bound.
      const double s = std::clamp(d.dot(W * r) / dWd, -max_slip_m, max_slip_m);
      best = std::min(best, chi2 - 2.0 * s * d.dot(W * r) + s * s * dWd);
    }
  }
  return std::max(best, 0.0);
}

SlidingWindowSmoother::SlidingWindowSmoother(const SmootherOptions& options, Atlas atlas)
    : options_(options),
      atlas_(std::move(atlas)),
      line_loss_(new ceres::SoftLOneLoss(options.line_loss_scale)),
      junction_loss_(new ceres::SoftLOneLoss(options.junction_loss_scale)),
      tracker_(options.mode == SmootherMode::kMapping ? options.tracker : options.upkeep.tracker) {
  assert(options_.Validate().ok());
  assert(atlas_.Validate().ok());
  for (const AtlasLine& line : atlas_.lines) {
    line_blocks_.push_back({line.line_map.rho_m, line.line_map.alpha_rad});
  }
  for (const AtlasJunction& junction : atlas_.junctions) {
    junction_blocks_.push_back({junction.point_m.x(), junction.point_m.y()});
  }
  line_retired_.assign(atlas_.lines.size(), false);
  line_born_.assign(atlas_.lines.size(), false);
  for (const AtlasLine& line : atlas_.lines) line_misses_.push_back(line.missed);
  junction_retired_.assign(atlas_.junctions.size(), false);
  junction_born_.assign(atlas_.junctions.size(), false);
  for (const AtlasJunction& junction : atlas_.junctions) {
    junction_misses_.push_back(junction.missed);
  }
}

SlidingWindowSmoother::~SlidingWindowSmoother() = default;

void SlidingWindowSmoother::Initialize(double stamp_s, const core::SE2& T_map_base,
                                       const core::Matrix3& covariance) {
  window_.clear();
  Keyframe keyframe;
  keyframe.stamp_s = stamp_s;
  keyframe.pose = {T_map_base.x(), T_map_base.y(), T_map_base.yaw()};
  window_.push_back(std::move(keyframe));
  MarginalPrior prior;
  prior.x0 = {{T_map_base.x(), T_map_base.y(), T_map_base.yaw()}};
  prior.is_pose = {true};
  prior.sqrt_prior.J = SqrtInformationFromCovariance(covariance).value();
  prior.sqrt_prior.r = Eigen::Vector3d::Zero();
  prior_ = std::make_unique<MarginalPriorFactor>(std::move(prior));
  latest_ = {stamp_s, T_map_base, covariance};
  keyframe_count_ = 1;
  line_in_window_.clear();
  line_in_pass_.clear();
  junction_in_window_.clear();
  junction_in_pass_.clear();
  chain_ = ChainState();
  InvalidateChain();
}

bool SlidingWindowSmoother::HoldKeyframe(double stamp_s, bool held) {
  for (Keyframe& keyframe : window_) {
    if (keyframe.stamp_s == stamp_s) {
      keyframe.held = held;
      return true;
    }
  }
  return false;
}

Atlas SlidingWindowSmoother::CurrentAtlas() const {
  Atlas atlas;
  atlas.frame = atlas_.frame;
  atlas.covariances_stated = atlas_.covariances_stated;
  for (size_t i = 0; i < atlas_.lines.size(); ++i) {
    if (line_retired_[i]) continue;
    atlas.lines.push_back(atlas_.lines[i]);
    atlas.lines.back().line_map = perception::NormalizeLine(line_blocks_[i][0], line_blocks_[i][1]);
    atlas.lines.back().missed = line_misses_[i];
  }
  for (size_t i = 0; i < atlas_.junctions.size(); ++i) {
    if (junction_retired_[i]) continue;
    atlas.junctions.push_back(atlas_.junctions[i]);
    atlas.junctions.back().point_m = {junction_blocks_[i][0], junction_blocks_[i][1]};
    atlas.junctions.back().missed = junction_misses_[i];
  }
  return atlas;
}

void SlidingWindowSmoother::AddLandmarkFactors(const FloorObservations& observations,
                                               const core::SE2& T_pred,
                                               const core::Matrix3& covariance_pred,
                                               const core::Matrix3& slip_covariance,
                                               Keyframe* keyframe, KeyframeHealth* health) {
  const bool mapping = options_.mode == SmootherMode::kMapping;
  if (mapping) {
    for (size_t i = 0; i < atlas_.lines.size(); ++i) {
      atlas_.lines[i].line_map = perception::NormalizeLine(line_blocks_[i][0], line_blocks_[i][1]);
    }
    for (size_t i = 0; i < atlas_.junctions.size(); ++i) {
      atlas_.junctions[i].point_m = {junction_blocks_[i][0], junction_blocks_[i][1]};
    }
  }
  std::vector<const LineObservation*> unmatched_lines;
  std::vector<const JunctionObservation*> unmatched_junctions;
  health->lines_observed = static_cast<int>(observations.lines.size());
  health->junctions_observed = static_cast<int>(observations.junctions.size());
  const bool upkeep = !mapping && options_.upkeep.enabled;
  // A landmark with a sightings record was estimated from a drive (the
  // mapper's, or born here): its covariance is that estimate's.
  const bool with_landmark_covariance = !mapping && options_.landmark_covariance_in_factors;
  const auto add_line = [&](const LineObservation& observation, int landmark) {
    Eigen::Matrix2d landmark_covariance = Eigen::Matrix2d::Zero();
    if (with_landmark_covariance &&
        (atlas_.covariances_stated || atlas_.lines[landmark].seen.has_value())) {
      Eigen::Matrix2d J;
      perception::InverseTransformLine(T_pred, atlas_.lines[landmark].line_map, nullptr, &J);
      landmark_covariance = J * atlas_.lines[landmark].covariance * J.transpose();
    }
    const auto sqrt_information =
        SqrtInformationFromCovariance2(observation.covariance + landmark_covariance);
    if (!sqrt_information.ok()) return false;
    keyframe->lines.push_back(
        {landmark, std::make_unique<GroundLineFactor>(observation.line_base, *sqrt_information),
         observation.covariance, landmark_covariance});
    return true;
  };
  const auto add_junction = [&](const JunctionObservation& observation, int landmark) {
    Eigen::Matrix2d landmark_covariance = Eigen::Matrix2d::Zero();
    if (with_landmark_covariance &&
        (atlas_.covariances_stated || atlas_.junctions[landmark].seen.has_value())) {
      const Eigen::Matrix2d R = T_pred.Rotation();
      landmark_covariance = R.transpose() * atlas_.junctions[landmark].covariance * R;
    }
    const auto sqrt_information =
        SqrtInformationFromCovariance2(observation.covariance + landmark_covariance);
    if (!sqrt_information.ok()) return false;
    keyframe->junctions.push_back(
        {landmark, std::make_unique<JunctionFactor>(observation.point_base_m, *sqrt_information),
         observation.covariance, landmark_covariance});
    return true;
  };
  std::vector<Match> line_matches = AssociateLines(
      observations.lines, atlas_, T_pred, covariance_pred, options_.association, &line_retired_);
  std::vector<Match> junction_matches =
      AssociateJunctions(observations.junctions, atlas_, T_pred, covariance_pred,
                         options_.association, &junction_retired_);
  const auto none_matched = [&] {
    int seen = 0;
    for (const std::vector<Match>* matches : {&line_matches, &junction_matches}) {
      for (const Match& m : *matches) {
        if (m.landmark >= 0 || m.ambiguous) return false;
        ++seen;
      }
    }
    return seen > 0;
  };
  if (!mapping && options_.slip_sigma_m > 0.0 && none_matched()) {
    const core::Matrix3 widened = covariance_pred + slip_covariance;
    std::vector<Match> lines = AssociateLines(observations.lines, atlas_, T_pred, widened,
                                              options_.association, &line_retired_);
    std::vector<Match> junctions = AssociateJunctions(
        observations.junctions, atlas_, T_pred, widened, options_.association, &junction_retired_);
    int matched = 0;
    for (const std::vector<Match>* matches : {&lines, &junctions}) {
      for (const Match& m : *matches) matched += m.landmark >= 0;
    }
    // One observation that fits only under a slip is more likely an outlier
    // (a misread marking) than a slip (~1.5e-3 per keyframe); two that fit
    // one slip together are not.
    if (matched >= options_.slip_min_matches) {
      line_matches = std::move(lines);
      junction_matches = std::move(junctions);
      health->slip_gate = true;
    }
  }
  bool born_moved = false;  // a born landmark's estimate changed
  std::vector<bool> lines_matched(upkeep ? atlas_.lines.size() : 0, false);
  std::vector<bool> junctions_matched(upkeep ? atlas_.junctions.size() : 0, false);
  for (const Match& match : line_matches) {
    const LineObservation& observation = observations.lines[match.observation];
    if (match.landmark >= 0 && add_line(observation, match.landmark)) {
      ++health->lines_used;
      if (upkeep) lines_matched[match.landmark] = true;
      if (upkeep && line_born_[match.landmark]) {
        // A landmark born on this drive goes on gaining precision and extent.
        AtlasLine& landmark = atlas_.lines[match.landmark];
        FuseLineSighting(LineInMap(observation, T_pred, covariance_pred), &landmark);
        line_blocks_[match.landmark] = {landmark.line_map.rho_m, landmark.line_map.alpha_rad};
        born_moved = true;
      }
      if (mapping) {
        AtlasLine& landmark = atlas_.lines[match.landmark];
        const AtlasLine seen = LineInMap(observation, T_pred, covariance_pred);
        ExtendLineExtent(seen.endpoint_a_m, &landmark);
        ExtendLineExtent(seen.endpoint_b_m, &landmark);
      }
      continue;
    }
    ++health->lines_rejected;
    if (match.ambiguous) {
      ++health->lines_ambiguous;
    } else if (mapping || (upkeep && !core::IsFaceKind(observation.kind) &&
                           match.nearest_mahalanobis2 > options_.upkeep.birth_novelty_chi2)) {
      unmatched_lines.push_back(&observation);
    }
  }
  for (const Match& match : junction_matches) {
    const JunctionObservation& observation = observations.junctions[match.observation];
    if (match.landmark >= 0 && add_junction(observation, match.landmark)) {
      ++health->junctions_used;
      if (upkeep) junctions_matched[match.landmark] = true;
      if (upkeep && junction_born_[match.landmark]) {
        AtlasJunction& landmark = atlas_.junctions[match.landmark];
        FuseJunctionSighting(JunctionInMap(observation, T_pred, covariance_pred), &landmark);
        junction_blocks_[match.landmark] = {landmark.point_m.x(), landmark.point_m.y()};
        born_moved = true;
      }
    } else if (!match.ambiguous &&
               (mapping ||
                (upkeep && match.nearest_mahalanobis2 > options_.upkeep.birth_novelty_chi2))) {
      unmatched_junctions.push_back(&observation);
    }
  }
  if (!mapping && !upkeep) return;
  if (born_moved) {
    // The window's terms on a moved landmark are stale.
    for (Keyframe& k : window_) k.chain.valid = false;
    InvalidateChain();
  }
  if (upkeep) {
    KeepAtlasCurrent(observations, T_pred, lines_matched, junctions_matched, health);
    // Births only from a keyframe localized on the atlas (AtlasUpkeepOptions).
    const double position_sigma_m = std::sqrt(covariance_pred.topLeftCorner<2, 2>()
                                                  .selfadjointView<Eigen::Upper>()
                                                  .eigenvalues()
                                                  .maxCoeff());
    if (health->lines_used + health->junctions_used < options_.upkeep.birth_min_matches ||
        !(position_sigma_m <= options_.upkeep.birth_max_position_sigma_m)) {
      unmatched_lines.clear();
      unmatched_junctions.clear();
    }
  }
  const LandmarkTracker::Confirmed confirmed = tracker_.Update(
      keyframe_count_, T_pred, covariance_pred, unmatched_lines, unmatched_junctions);
  const auto sighting = [&] { return LandmarkSightings{1, health->stamp_s, health->stamp_s}; };
  for (const auto& [line, observation] : confirmed.lines) {
    AtlasLine landmark = line;
    landmark.id = 0;
    for (const AtlasLine& l : atlas_.lines) landmark.id = std::max(landmark.id, l.id + 1);
    if (upkeep) landmark.seen = sighting();
    atlas_.lines.push_back(landmark);
    line_blocks_.push_back({landmark.line_map.rho_m, landmark.line_map.alpha_rad});
    line_retired_.push_back(false);
    line_misses_.push_back(0);
    line_born_.push_back(upkeep);
    add_line(*unmatched_lines[observation], static_cast<int>(atlas_.lines.size()) - 1);
    ++health->landmarks_added;
  }
  for (const auto& [junction, observation] : confirmed.junctions) {
    AtlasJunction landmark = junction;
    landmark.id = 0;
    for (const AtlasJunction& j : atlas_.junctions) landmark.id = std::max(landmark.id, j.id + 1);
    if (upkeep) landmark.seen = sighting();
    atlas_.junctions.push_back(landmark);
    junction_blocks_.push_back({landmark.point_m.x(), landmark.point_m.y()});
    junction_retired_.push_back(false);
    junction_misses_.push_back(0);
    junction_born_.push_back(upkeep);
    add_junction(*unmatched_junctions[observation], static_cast<int>(atlas_.junctions.size()) - 1);
    ++health->landmarks_added;
  }
  if (upkeep) {
    landmarks_born_ += static_cast<int>(confirmed.lines.size() + confirmed.junctions.size());
  }
}

core::Result<KeyframeHealth> SlidingWindowSmoother::AddKeyframe(
    double stamp_s, const RelativeMotion& motion, const FloorObservations& observations,
    const std::optional<RelativePoseMeasurement>& relative) {
  assert(initialized());
  if (relative &&
      (!relative->T_prev_curr.Log().allFinite() || !relative->sqrt_information.allFinite())) {
    return core::Status::Error("keyframe at " + std::to_string(stamp_s) +
                               " s: relative measurement is not finite");
  }
  const Clock::time_point start = Clock::now();
  KeyframeHealth health;
  health.stamp_s = stamp_s;
  PoseEstimate predicted = PropagateFromKeyframe(latest_, motion, stamp_s);
  core::Matrix3 odometry_covariance =
      0.5 * (motion.covariance + motion.covariance.transpose()) + OdometryCovarianceFloor(options_);
  bool use_relative = relative.has_value();
  if (relative) {
    const core::Vector3 r = motion.T_start_end.Between(relative->T_prev_curr).Log();
    const core::Matrix3 W = core::DifferenceInformation<3>(
        odometry_covariance, relative->sqrt_information.transpose() * relative->sqrt_information);
    health.relative_chi2 = r.dot(W * r);
    if (options_.slip_sigma_m > 0.0 && options_.slip_relative_chi2 > 0.0 &&
        health.relative_chi2 > options_.slip_relative_chi2) {
      health.slip_residual_chi2 =
          OneWheelSlipResidualChi2(motion, r, W, options_.track_m, 3.0 * options_.slip_sigma_m);
      // A slip has one parameter: it explains any disagreement in a single
      // constrained direction (a match that fixes the heading only), so
      // there it cannot be told from a wrong match and the wheels are kept.
      if (MeasurementRank(relative->sqrt_information) >= 2 &&
          (options_.slip_residual_chi2 <= 0.0 ||
           health.slip_residual_chi2 <= options_.slip_residual_chi2)) {
        const core::Matrix3 slip = SlipCovariance(motion, options_.slip_sigma_m, options_.track_m);
        odometry_covariance += slip;
        predicted.covariance += slip;  // the lines' gate too
        health.slip_from_relative = true;
      } else {
        use_relative = false;
        health.relative_rejected = true;
      }
    }
  }
  const auto odometry_sqrt = SqrtInformationFromCovariance(odometry_covariance);
  if (!odometry_sqrt.ok()) {
    return odometry_sqrt.status().WithContext("keyframe at " + std::to_string(stamp_s) +
                                              " s: odometry covariance");
  }
  Keyframe keyframe;
  keyframe.stamp_s = stamp_s;
  keyframe.pose = {predicted.T_map_base.x(), predicted.T_map_base.y(), predicted.T_map_base.yaw()};
  keyframe.between.push_back(
      std::make_unique<RelativePoseFactor>(motion.T_start_end, *odometry_sqrt));
  if (use_relative) {
    keyframe.between.push_back(
        std::make_unique<RelativePoseFactor>(relative->T_prev_curr, relative->sqrt_information));
    health.relative_measurement_used = true;
  }
  ++keyframe_count_;
  AddLandmarkFactors(observations, predicted.T_map_base, predicted.covariance,
                     SlipCovariance(motion, options_.slip_sigma_m, options_.track_m), &keyframe,
                     &health);
  window_.push_back(std::move(keyframe));
  latest_ = predicted;
  CountSightings(window_.back(), true);
  if (core::Status s = ReweightSharedLandmarks(); !s.ok()) {
    return s.WithContext("keyframe at " + std::to_string(stamp_s) + " s");
  }

  core::Status status = Solve(&health);
  while (status.ok() && window_.size() > 2 && !window_.front().held &&
         window_.back().stamp_s - window_.front().stamp_s > options_.window_s) {
    status = MarginalizeOldest();
  }
  if (!status.ok()) return status;
  const auto information = NewestInformation();
  if (!information.ok()) return information.status();
  latest_ = {stamp_s, core::PoseFromAmbient(window_.back().pose),
             information->completeOrthogonalDecomposition().pseudoInverse()};
  health.window_size = static_cast<int>(window_.size());
  health.update_time_s = SecondsSince(start);
  return health;
}

void SlidingWindowSmoother::CountSightings(const Keyframe& keyframe, bool added) {
  if (!SharesLandmarkError()) return;
  const auto count = [added](const auto& factors, std::size_t landmarks,
                             std::vector<int>* in_window, std::vector<int>* in_pass) {
    in_window->resize(landmarks, 0);
    in_pass->resize(landmarks, 0);
    for (const auto& factor : factors) {
      if (factor.landmark_covariance.isZero(0.0)) continue;
      int& window = (*in_window)[factor.landmark];
      int& pass = (*in_pass)[factor.landmark];
      if (added) {
        ++window;
        ++pass;
      } else if (--window <= 0) {
        // Out of the window: the next sighting starts a new pass (the prior
        // keeps what this one's factors held).
        window = 0;
        pass = 0;
      }
    }
  };
  count(keyframe.lines, atlas_.lines.size(), &line_in_window_, &line_in_pass_);
  count(keyframe.junctions, atlas_.junctions.size(), &junction_in_window_, &junction_in_pass_);
}

core::Status SlidingWindowSmoother::ReweightSharedLandmarks() {
  if (!SharesLandmarkError()) return core::Status::Ok();
  const auto reweight = [](auto* factors, const std::vector<int>& in_pass, Keyframe* keyframe) {
    for (auto& factor : *factors) {
      if (factor.landmark_covariance.isZero(0.0)) continue;
      const int shared_by = std::max(1, in_pass[factor.landmark]);
      if (shared_by == factor.shared_by) continue;
      const auto sqrt_information = SqrtInformationFromCovariance2(
          factor.observation_covariance + shared_by * factor.landmark_covariance);
      if (!sqrt_information.ok()) return sqrt_information.status();
      factor.cost->set_sqrt_information(*sqrt_information);
      factor.shared_by = shared_by;
      keyframe->chain.valid = false;
    }
    return core::Status::Ok();
  };
  for (Keyframe& keyframe : window_) {
    if (core::Status s = reweight(&keyframe.lines, line_in_pass_, &keyframe); !s.ok())
      return s.WithContext("a line landmark's shared weight");
    if (core::Status s = reweight(&keyframe.junctions, junction_in_pass_, &keyframe); !s.ok())
      return s.WithContext("a junction landmark's shared weight");
  }
  return core::Status::Ok();
}

std::vector<LinearizationFactor> SlidingWindowSmoother::UnaryFactors(
    const Keyframe& keyframe, std::vector<LinearizationVariable>* variables) {
  std::vector<LinearizationFactor> factors;
  for (const auto& factor : keyframe.lines) {
    variables->push_back({line_blocks_[factor.landmark].data(), 2, false});
    factors.push_back(
        {factor.cost.get(), line_loss_.get(), {0, static_cast<int>(variables->size()) - 1}});
  }
  for (const auto& factor : keyframe.junctions) {
    variables->push_back({junction_blocks_[factor.landmark].data(), 2, false});
    factors.push_back(
        {factor.cost.get(), junction_loss_.get(), {0, static_cast<int>(variables->size()) - 1}});
  }
  return factors;
}

core::Status SlidingWindowSmoother::MarginalizeOldest() {
  Keyframe& front = window_[0];
  Keyframe& second = window_[1];
  // Variables: the oldest pose, the next pose, then the landmarks (held fixed:
  // in neither set, so their coupling is dropped).
  std::vector<LinearizationVariable> variables = {{front.pose.data(), 3, true},
                                                  {second.pose.data(), 3, true}};
  // Localization mode: the landmarks are fixed, so their factors are unary
  // on the pose and belong in the prior. Mapping mode: the landmarks are
  // estimates still moving; linearizing their factors with the landmarks held
  // fixed would count them as exact and anchor the prior to their current
  // values, so they are left out (information dropped, not invented).
  std::vector<LinearizationFactor> factors;
  if (options_.mode == SmootherMode::kLocalization) factors = UnaryFactors(front, &variables);
  factors.push_back({prior_.get(), nullptr, {0}});
  for (const auto& between : second.between) factors.push_back({between.get(), nullptr, {0, 1}});
  const auto system = LinearizeFactors(variables, factors);
  if (!system.ok()) return system.status().WithContext("marginalization");
  const std::vector<int> keep = {3, 4, 5};
  const std::vector<int> marginalize = {0, 1, 2};
  const auto reduced = MarginalizeSchur(*system, keep, marginalize);
  if (!reduced.ok()) return reduced.status();
  auto sqrt_prior = SqrtPriorFromSystem(*reduced);
  if (!sqrt_prior.ok()) return sqrt_prior.status();
  MarginalPrior prior;
  prior.x0 = {{second.pose[0], second.pose[1], second.pose[2]}};
  prior.is_pose = {true};
  prior.sqrt_prior = std::move(sqrt_prior).value();
  prior_ = std::make_unique<MarginalPriorFactor>(std::move(prior));
  second.between.clear();
  second.chain.valid = false;
  CountSightings(front, false);
  window_.pop_front();
  InvalidateChain();
  return core::Status::Ok();
}

}  // namespace groundline::localization
