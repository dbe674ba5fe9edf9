#include "groundline/core/relation_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <numbers>
#include <optional>
#include <string>

#include "groundline/core/angles.h"
#include "groundline/core/trajectory_io.h"

namespace groundline::core {
namespace {

// The pose nearest stamp_s if within max_dt_s.
std::optional<SE2> NearestPose(const Trajectory& trajectory, double stamp_s, double max_dt_s) {
  const auto it = std::lower_bound(trajectory.begin(), trajectory.end(), stamp_s,
                                   [](const StampedPose& p, double t) { return p.stamp_s < t; });
  const StampedPose* best = nullptr;
  if (it != trajectory.end()) best = &*it;
  if (it != trajectory.begin()) {
    const StampedPose& before = *std::prev(it);
    if (best == nullptr || stamp_s - before.stamp_s <= best->stamp_s - stamp_s) best = &before;
  }
  if (best == nullptr || std::abs(best->stamp_s - stamp_s) > max_dt_s) return std::nullopt;
  return best->pose;
}

}  // namespace

Status RelationMetricsOptions::Validate() const {
  if (!(max_dt_s >= 0.0) || !std::isfinite(max_dt_s)) {
    return Status::Error("relation max_dt_s must be finite and >= 0 [s], got " +
                         std::to_string(max_dt_s));
  }
  return Status::Ok();
}

Result<std::vector<RelationError>> ComputeRelationErrorList(const Trajectory& estimate,
                                                            const std::vector<Relation>& relations,
                                                            const RelationMetricsOptions& options,
                                                            std::size_t* n_skipped) {
  if (Status s = options.Validate(); !s.ok()) return s;
  if (estimate.empty()) return Status::Error("the estimate trajectory is empty");
  if (Status s = ValidateTrajectory(estimate, "estimate"); !s.ok()) return s;
  std::vector<RelationError> errors;
  errors.reserve(relations.size());
  std::size_t skipped = 0;
  for (const Relation& relation : relations) {
    const std::optional<SE2> T_est_1 = NearestPose(estimate, relation.t1_s, options.max_dt_s);
    const std::optional<SE2> T_est_2 = NearestPose(estimate, relation.t2_s, options.max_dt_s);
    if (!T_est_1 || !T_est_2) {
      ++skipped;
      continue;
    }
    const SE2 delta_est = T_est_1->Between(*T_est_2);
    const SE2 error = relation.delta.Between(delta_est);
    errors.push_back(
        {relation.t1_s, relation.t2_s, error.translation().norm(), std::abs(error.yaw())});
  }
  if (n_skipped != nullptr) *n_skipped = skipped;
  return errors;
}

Result<RelationErrorSummary> ComputeRelationErrors(const Trajectory& estimate,
                                                   const std::vector<Relation>& relations,
                                                   const RelationMetricsOptions& options) {
  if (relations.empty()) return Status::Error("no relations to evaluate");
  std::size_t n_skipped = 0;
  Result<std::vector<RelationError>> errors =
      ComputeRelationErrorList(estimate, relations, options, &n_skipped);
  if (!errors.ok()) return errors.status();
  if (errors->empty()) {
    double first_s = relations.front().t1_s;
    double last_s = first_s;
    for (const Relation& r : relations) {
      first_s = std::min({first_s, r.t1_s, r.t2_s});
      last_s = std::max({last_s, r.t1_s, r.t2_s});
    }
    char text[240];
    std::snprintf(text, sizeof(text),
                  "none of the %zu relations (stamps %.6f to %.6f s) has estimate poses within "
                  "%.4g s of both ends; the estimate spans [%.6f, %.6f] s: check the clock, or "
                  "raise --max-dt-s",
                  relations.size(), first_s, last_s, options.max_dt_s, estimate.front().stamp_s,
                  estimate.back().stamp_s);
    return Status::Error(text);
  }
  std::vector<double> trans_m, rot_deg;
  for (const RelationError& e : *errors) {
    trans_m.push_back(e.trans_m);
    rot_deg.push_back(e.rot_rad * kRadToDeg);
  }
  RelationErrorSummary summary;
  summary.n_used = errors->size();
  summary.n_skipped = n_skipped;
  summary.trans_m = ComputeErrorStats(std::move(trans_m));
  summary.rot_deg = ComputeErrorStats(std::move(rot_deg));
  return summary;
}

}  // namespace groundline::core
