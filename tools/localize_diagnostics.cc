#include "localize_diagnostics.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "groundline/core/trajectory_association.h"

namespace groundline::tools {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
// The true pose's covariance for the reference association: the extractor's
// lines are not exact, so the truth gets the slack of a good estimate.
constexpr double kTruthSigmaM = 0.01;
constexpr double kTruthSigmaRad = 0.3 * std::numbers::pi / 180.0;

}  // namespace

LocalizeDiagnostics::LocalizeDiagnostics(const core::Trajectory& ground_truth,
                                         localization::Atlas atlas,
                                         const localization::AssociationOptions& association)
    : ground_truth_(ground_truth), atlas_(std::move(atlas)), association_(association) {}

core::SE2 LocalizeDiagnostics::TruePose(double stamp_s) const {
  const auto later =
      std::lower_bound(ground_truth_.begin(), ground_truth_.end(), stamp_s,
                       [](const core::StampedPose& p, double t) { return p.stamp_s < t; });
  if (later == ground_truth_.begin()) return later->pose;
  if (later == ground_truth_.end()) return ground_truth_.back().pose;
  const core::StampedPose& a = *(later - 1);
  const double fraction = (stamp_s - a.stamp_s) / (later->stamp_s - a.stamp_s);
  return core::InterpolateSE2(a.pose, later->pose, fraction);
}

nlohmann::ordered_json LocalizeDiagnostics::Errors(const localization::PoseEstimate& estimate,
                                                   const char* prefix) const {
  const core::SE2 truth = TruePose(estimate.stamp_s);
  const core::Vector2 u =
      core::ReferenceDirectionOfTravel(ground_truth_, estimate.stamp_s, core::AssociationOptions());
  const core::Vector2 e = estimate.T_map_base.translation() - truth.translation();
  const std::string p(prefix);
  nlohmann::ordered_json out;
  out[p + "along_m"] = e.dot(u);
  out[p + "cross_m"] = e.dot(core::Vector2(-u.y(), u.x()));
  out[p + "yaw_deg"] = (truth.Inverse() * estimate.T_map_base).yaw() * kRadToDeg;
  out[p + "sigma_along_m"] = std::sqrt(std::max(
      0.0, u.dot(estimate.T_map_base.Rotation() * estimate.covariance.topLeftCorner<2, 2>() *
                 estimate.T_map_base.Rotation().transpose() * u)));
  return out;
}

nlohmann::ordered_json LocalizeDiagnostics::BeforeUpdate(
    const localization::PoseEstimate& predicted,
    const localization::FloorObservations& observations) const {
  nlohmann::ordered_json out = Errors(predicted, "pred_");
  const core::SE2 truth = TruePose(predicted.stamp_s);
  const core::Matrix3 truth_covariance =
      core::Vector3(kTruthSigmaM * kTruthSigmaM, kTruthSigmaM * kTruthSigmaM,
                    kTruthSigmaRad * kTruthSigmaRad)
          .asDiagonal();
  const std::vector<localization::Match> at_prediction = localization::AssociateLines(
      observations.lines, atlas_, predicted.T_map_base, predicted.covariance, association_);
  const std::vector<localization::Match> at_truth = localization::AssociateLines(
      observations.lines, atlas_, truth, truth_covariance, association_);
  int right = 0, wrong = 0, unverified = 0, missed = 0;
  nlohmann::ordered_json wrong_pairs = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < at_prediction.size(); ++i) {
    const int used = at_prediction[i].landmark;
    const int true_landmark = at_truth[i].landmark;
    if (used < 0) {
      if (true_landmark >= 0) ++missed;
      continue;
    }
    if (true_landmark < 0) {
      ++unverified;
    } else if (true_landmark == used ||
               (perception::LineDifference(atlas_.lines[used].line_map,
                                           atlas_.lines[true_landmark].line_map)
                    .cwiseAbs()
                    .maxCoeff() < association_.duplicate_rho_m)) {
      ++right;
    } else {
      ++wrong;
      wrong_pairs.push_back({atlas_.lines[used].id, atlas_.lines[true_landmark].id});
    }
  }
  out["assoc_right"] = right;
  out["assoc_wrong"] = wrong;
  out["assoc_unverified"] = unverified;
  out["assoc_missed"] = missed;
  if (!wrong_pairs.empty()) out["wrong_used_true_ids"] = wrong_pairs;
  return out;
}

nlohmann::ordered_json LocalizeDiagnostics::AfterUpdate(
    const localization::PoseEstimate& estimate) const {
  return Errors(estimate, "err_");
}

}  // namespace groundline::tools
