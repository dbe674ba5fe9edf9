// Matching an estimated trajectory to a reference by timestamp: the first step
// of every trajectory metric (see docs/metrics.md).
//
// For each estimate pose at stamp t the reference pose "at t" is either
// - kNearest: the reference pose whose stamp is nearest t, if |dt| <= max_dt_s;
// - kInterpolate: the reference interpolated on SE(2) between the bracketing
//   poses a (t_a <= t) and b (t_b >= t):  T_ref(t) = T_a * Exp(s * Log(T_a^-1 T_b)),
//   s = (t - t_a) / (t_b - t_a) (constant twist between the two poses); the
//   bracket must be at most max_interpolation_gap_s long. An estimate stamp
//   outside the reference's time span but within max_dt_s of its first or last
//   pose takes that end pose (no extrapolation).
// Estimate poses with no reference are counted as unmatched, never dropped silently.
//
// The reference direction of travel at t (the unit tangent of the reference
// path, used for the along-track / cross-track split) is the direction of the
// chord p_ref(k) - p_ref(j) between the nearest reference poses j <= t <= k,
// widened symmetrically one pose at a time until the chord is at least
// tangent_baseline_m long. If it is still shorter once the window spans
// tangent_window_s (the robot stands still or turns on the spot), the
// reference heading (cos yaw, sin yaw) at t is used instead. When the robot
// reverses, the tangent points backwards: the along-track sign flips, its RMSE
// does not.
//
// All functions are pure and thread-safe.
#ifndef GROUNDLINE_CORE_TRAJECTORY_ASSOCIATION_H_
#define GROUNDLINE_CORE_TRAJECTORY_ASSOCIATION_H_

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"

namespace groundline::core {

enum class AssociationMethod { kNearest, kInterpolate };

// "nearest" / "interp".
const char* AssociationMethodName(AssociationMethod method);

struct AssociationOptions {
  AssociationMethod method = AssociationMethod::kNearest;
  // Largest |t_est - t_ref| for a nearest match [s] (and, for interpolation,
  // how far outside the reference's time span an estimate may lie).
  double max_dt_s = 0.01;
  // Longest reference gap that interpolation bridges [s].
  double max_interpolation_gap_s = 1.0;
  // Shortest reference chord that defines the direction of travel [m].
  double tangent_baseline_m = 0.05;
  // Longest time window searched for that chord before falling back to the
  // reference heading [s].
  double tangent_window_s = 2.0;

  // Ok, or which field is out of range and why.
  Status Validate() const;
};

// One estimate pose and the reference at its stamp, both in the map frame.
struct PosePair {
  double stamp_s = 0.0;  // the estimate's stamp
  SE2 T_map_est;
  SE2 T_map_ref;
  // Unit tangent of the reference path at stamp_s, in the map frame.
  Vector2 ref_direction_map = Vector2::UnitX();
  // True when ref_direction_map fell back to the reference heading.
  bool direction_from_heading = false;
  // The estimate's covariance, if it carried one (right perturbation, x y yaw).
  std::optional<Matrix3> est_covariance;
};

struct Association {
  std::vector<PosePair> pairs;  // in estimate order (increasing stamp)
  std::size_t n_unmatched = 0;  // estimate poses without a reference
};

// Matches `estimate` to `reference`. Errors (never asserts) when either is
// empty, not strictly increasing in time or non-finite, when the options are
// invalid, or when no estimate pose matches; the message gives both time spans.
Result<Association> AssociateByStamp(const Trajectory& estimate, const Trajectory& reference,
                                     const AssociationOptions& options = {});

// a * Exp(fraction * Log(a^-1 * b)): a at 0, b at 1.
SE2 InterpolateSE2(const SE2& a, const SE2& b, double fraction);

// The pose of a sorted, non-empty trajectory at a stamp, interpolated
// linearly in x, y and (shortest-way) yaw between the bracketing poses (at
// odometry or simulation rates the difference from InterpolateSE2 is far
// below a micrometre); clamped to the first and last pose outside its span.
SE2 InterpolatePose(const Trajectory& trajectory, double stamp_s);

// The unit tangent of the reference path at stamp_s, as described above.
// Sets *from_heading (if non-null) when the heading fallback was used.
// `reference` must be non-empty and sorted.
Vector2 ReferenceDirectionOfTravel(const Trajectory& reference, double stamp_s,
                                   const AssociationOptions& options, bool* from_heading = nullptr);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_TRAJECTORY_ASSOCIATION_H_
