#include "groundline/core/trajectory_association.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "groundline/core/trajectory_io.h"

namespace groundline::core {
namespace {

// Index of the first pose with stamp >= t (size() if none).
std::size_t LowerBound(const Trajectory& trajectory, double stamp_s) {
  const auto it = std::lower_bound(trajectory.begin(), trajectory.end(), stamp_s,
                                   [](const StampedPose& p, double t) { return p.stamp_s < t; });
  return static_cast<std::size_t>(std::distance(trajectory.begin(), it));
}

// Index of the pose nearest stamp_s in time.
std::size_t NearestIndex(const Trajectory& trajectory, double stamp_s) {
  const std::size_t k = LowerBound(trajectory, stamp_s);
  if (k == 0) return 0;
  if (k == trajectory.size()) return k - 1;
  return (stamp_s - trajectory[k - 1].stamp_s) <= (trajectory[k].stamp_s - stamp_s) ? k - 1 : k;
}

// The reference at stamp_s under `options`, or nullopt if there is none.
std::optional<SE2> ReferenceAt(const Trajectory& reference, double stamp_s,
                               const AssociationOptions& options) {
  const std::size_t nearest = NearestIndex(reference, stamp_s);
  const double nearest_dt_s = std::abs(reference[nearest].stamp_s - stamp_s);
  if (options.method == AssociationMethod::kNearest) {
    if (nearest_dt_s <= options.max_dt_s) return reference[nearest].pose;
    return std::nullopt;
  }
  const std::size_t k = LowerBound(reference, stamp_s);
  if (k < reference.size() && reference[k].stamp_s == stamp_s) return reference[k].pose;
  if (k == 0 || k == reference.size()) {
    // Outside the reference's span: only its end pose, and only close by.
    if (nearest_dt_s <= options.max_dt_s) return reference[nearest].pose;
    return std::nullopt;
  }
  const StampedPose& a = reference[k - 1];
  const StampedPose& b = reference[k];
  if (b.stamp_s - a.stamp_s > options.max_interpolation_gap_s) return std::nullopt;
  return InterpolateSE2(a.pose, b.pose, (stamp_s - a.stamp_s) / (b.stamp_s - a.stamp_s));
}

std::string Span(const Trajectory& trajectory) {
  char text[96];
  std::snprintf(text, sizeof(text), "[%.6f, %.6f] s (%zu poses)", trajectory.front().stamp_s,
                trajectory.back().stamp_s, trajectory.size());
  return text;
}

}  // namespace

const char* AssociationMethodName(AssociationMethod method) {
  return method == AssociationMethod::kNearest ? "nearest" : "interp";
}

Status AssociationOptions::Validate() const {
  if (!(max_dt_s >= 0.0) || !std::isfinite(max_dt_s)) {
    return Status::Error("association max_dt_s must be finite and >= 0 [s], got " +
                         std::to_string(max_dt_s));
  }
  if (!(max_interpolation_gap_s > 0.0)) {
    return Status::Error("association max_interpolation_gap_s must be > 0 [s], got " +
                         std::to_string(max_interpolation_gap_s));
  }
  if (!(tangent_baseline_m > 0.0) || !std::isfinite(tangent_baseline_m)) {
    return Status::Error("association tangent_baseline_m must be finite and > 0 [m], got " +
                         std::to_string(tangent_baseline_m));
  }
  if (!(tangent_window_s >= 0.0) || !std::isfinite(tangent_window_s)) {
    return Status::Error("association tangent_window_s must be finite and >= 0 [s], got " +
                         std::to_string(tangent_window_s));
  }
  return Status::Ok();
}

SE2 InterpolateSE2(const SE2& a, const SE2& b, double fraction) {
  return a * SE2::Exp(fraction * a.Between(b).Log());
}

Vector2 ReferenceDirectionOfTravel(const Trajectory& reference, double stamp_s,
                                   const AssociationOptions& options, bool* from_heading) {
  assert(!reference.empty());
  const std::size_t n = reference.size();
  const std::size_t lower = LowerBound(reference, stamp_s);
  // Start from the bracket t_j <= t <= t_k (one pose if t hits a stamp or
  // lies outside the reference's span).
  std::size_t j = 0;
  std::size_t k = 0;
  if (lower == n) {
    j = k = n - 1;
  } else if (lower == 0 || reference[lower].stamp_s == stamp_s) {
    j = k = lower;
  } else {
    j = lower - 1;
    k = lower;
  }
  if (from_heading != nullptr) *from_heading = false;
  while (true) {
    const Vector2 chord_m = reference[k].pose.translation() - reference[j].pose.translation();
    const double length_m = chord_m.norm();
    if (length_m >= options.tangent_baseline_m) return chord_m / length_m;
    const bool can_widen = j > 0 || k + 1 < n;
    if (!can_widen || reference[k].stamp_s - reference[j].stamp_s >= options.tangent_window_s) {
      break;
    }
    if (j > 0) --j;
    if (k + 1 < n) ++k;
  }
  if (from_heading != nullptr) *from_heading = true;
  const double yaw_rad = reference[NearestIndex(reference, stamp_s)].pose.yaw();
  return {std::cos(yaw_rad), std::sin(yaw_rad)};
}

Result<Association> AssociateByStamp(const Trajectory& estimate, const Trajectory& reference,
                                     const AssociationOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  if (estimate.empty()) return Status::Error("the estimate trajectory is empty");
  if (reference.empty()) return Status::Error("the reference trajectory is empty");
  if (Status s = ValidateTrajectory(estimate, "estimate"); !s.ok()) return s;
  if (Status s = ValidateTrajectory(reference, "reference"); !s.ok()) return s;

  Association association;
  association.pairs.reserve(estimate.size());
  for (const StampedPose& est : estimate) {
    const std::optional<SE2> ref = ReferenceAt(reference, est.stamp_s, options);
    if (!ref) {
      ++association.n_unmatched;
      continue;
    }
    PosePair pair;
    pair.stamp_s = est.stamp_s;
    pair.T_map_est = est.pose;
    pair.T_map_ref = *ref;
    pair.ref_direction_map =
        ReferenceDirectionOfTravel(reference, est.stamp_s, options, &pair.direction_from_heading);
    pair.est_covariance = est.covariance;
    association.pairs.push_back(std::move(pair));
  }
  if (association.pairs.empty()) {
    char limits[160];
    std::snprintf(limits, sizeof(limits), "(%s, max_dt_s %.4g s, max_interpolation_gap_s %.4g s)",
                  AssociationMethodName(options.method), options.max_dt_s,
                  options.max_interpolation_gap_s);
    return Status::Error("no estimate pose matches the reference in time " + std::string(limits) +
                         ": estimate spans " + Span(estimate) + ", reference spans " +
                         Span(reference) +
                         "; check that both use the same clock, or raise --max-dt-s");
  }
  return association;
}

SE2 InterpolatePose(const Trajectory& trajectory, double stamp_s) {
  assert(!trajectory.empty());
  if (stamp_s <= trajectory.front().stamp_s) return trajectory.front().pose;
  if (stamp_s >= trajectory.back().stamp_s) return trajectory.back().pose;
  const auto it = std::upper_bound(trajectory.begin(), trajectory.end(), stamp_s,
                                   [](double t, const StampedPose& p) { return t < p.stamp_s; });
  const StampedPose& b = *it;
  const StampedPose& a = *(it - 1);
  const double f = (stamp_s - a.stamp_s) / (b.stamp_s - a.stamp_s);
  const Vector2 p = a.pose.translation() + f * (b.pose.translation() - a.pose.translation());
  return SE2(p, a.pose.yaw() + f * WrapAngle(b.pose.yaw() - a.pose.yaw()));
}

}  // namespace groundline::core
