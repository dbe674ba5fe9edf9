// Trajectory accuracy metrics against a reference trajectory, as defined in
// EVAL.md and derived in docs/metrics.md: ATE, along-track (slip) and
// cross-track error, heading error, RPE and NEES consistency. The Kuemmerle
// relation metric is in relation_metrics.h, the JSON/table keys in
// metric_fields.h.
//
// Conventions (all poses T_map_base, SE(2) as in se2.h):
// - Position error e_p = p_est - p_ref in the map frame [m]; ATE statistics
//   are over |e_p|.
// - Along-track = e_p . u, cross-track = e_p . n, with u the reference's unit
//   direction of travel (trajectory_association.h) and n = (-u_y, u_x) its
//   left normal: along > 0 means the estimate is ahead, cross > 0 to the left.
// - Heading error = wrap(yaw_est - yaw_ref) in (-pi, pi].
// - NEES = e^T Sigma^-1 e, e = Log(T_est^-1 * T_ref) = T_ref (-) T_est, the
//   reference in the estimate's tangent space (right perturbation, the
//   covariance convention of trajectory.h). For a consistent 3-dof estimator
//   it is chi-square(3) distributed; the two-sided 95 % band is
//   [kNeesLower95Dof3, kNeesUpper95Dof3].
// - No alignment by default (a localization must be right in the map frame).
//   With alignment, the estimate is first mapped by the closed-form SE(2)
//   least-squares fit T_ref_est (AlignSE2) and all errors use T_ref_est * T_est.
//
// All functions are pure and thread-safe.
#ifndef GROUNDLINE_CORE_TRAJECTORY_METRICS_H_
#define GROUNDLINE_CORE_TRAJECTORY_METRICS_H_

#include <cstddef>
#include <optional>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/core/trajectory_association.h"

namespace groundline::core {

// Quantiles 0.025 and 0.975 of chi-square with 3 degrees of freedom.
inline constexpr double kNeesLower95Dof3 = 0.2158;
inline constexpr double kNeesUpper95Dof3 = 9.3484;

// Statistics of a set of non-negative or signed values. `std_dev` is the
// population standard deviation (divide by n), the convention that reproduces
// the published Kuemmerle relation figures (docs/metrics.md). All zero if n = 0.
struct ErrorStats {
  std::size_t n = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double std_dev = 0.0;
  double median = 0.0;  // mean of the two middle values for even n
  double max = 0.0;
};
ErrorStats ComputeErrorStats(std::vector<double> values);

// Closed-form least-squares rigid motion in the plane (Umeyama 1991 without
// scale; Horn's solution in 2D): T_ref_est minimizing
// sum_i |p_ref_i - T_ref_est * p_est_i|^2. With centred points a_i (estimate)
// and b_i (reference), yaw = atan2(sum a_i x b_i, sum a_i . b_i) and
// t = mean(b) - R mean(a). Error if the sizes differ, fewer than 2 points, or
// the points are (nearly) coincident so that the rotation is undetermined.
Result<SE2> AlignSE2(const std::vector<Vector2>& p_est_m, const std::vector<Vector2>& p_ref_m);

// Relative pose error over a fixed frame step or a travelled distance: for
// each matched pair i and its partner j (i + delta_frames, or the first pair
// whose reference path length from i reaches delta_m),
// E = (T_ref_i^-1 T_ref_j)^-1 (T_est_i^-1 T_est_j); translational error |t(E)|,
// rotational |yaw(E)|. Invariant to any alignment.
enum class RpeDeltaUnit { kFrames, kMetres };
struct RpeOptions {
  RpeDeltaUnit unit = RpeDeltaUnit::kMetres;
  double delta = 1.0;  // frames (a positive integer) or metres (> 0)
  Status Validate() const;
};
struct RpeSummary {
  RpeOptions options;
  ErrorStats trans_m;
  ErrorStats rot_deg;
};
// Error if no pair has a partner at the requested delta.
Result<RpeSummary> ComputeRpe(const std::vector<PosePair>& pairs, const RpeOptions& options);

// The errors of one matched pose (after alignment, if any).
struct PoseError {
  double stamp_s = 0.0;
  Vector2 position_error_map_m = Vector2::Zero();  // p_est - p_ref
  double along_m = 0.0;
  double cross_m = 0.0;
  double heading_error_rad = 0.0;
  std::optional<double> nees;  // if the estimate has a positive-definite covariance
};
// T_ref_est is applied to every estimate pose first (identity: no alignment).
std::vector<PoseError> ComputePoseErrors(const std::vector<PosePair>& pairs,
                                         const SE2& T_ref_est = SE2());

struct NeesSummary {
  std::size_t n = 0;                     // poses with a usable covariance
  std::size_t n_invalid_covariance = 0;  // covariances present but not positive definite
  double mean = 0.0;
  double in_band_share = 0.0;  // share of n with NEES in [kNeesLower95Dof3, kNeesUpper95Dof3]
};

struct TrajectoryMetricsOptions {
  AssociationOptions association;
  bool align = false;             // fit and apply T_ref_est (AlignSE2) first
  std::optional<RpeOptions> rpe;  // compute RPE if set
  Status Validate() const;
};

struct TrajectoryErrorSummary {
  std::size_t n_matched = 0;
  std::size_t n_unmatched = 0;
  AssociationMethod association_method = AssociationMethod::kNearest;
  ErrorStats ate_m;  // over |p_est - p_ref|
  double along_rmse_m = 0.0;
  double cross_rmse_m = 0.0;
  double heading_rmse_deg = 0.0;
  // Matched poses whose direction of travel fell back to the reference heading.
  std::size_t n_direction_from_heading = 0;
  std::optional<SE2> T_ref_est;     // the applied alignment, when options.align
  std::optional<NeesSummary> nees;  // when some estimate pose carries a covariance
  std::optional<RpeSummary> rpe;    // when options.rpe
};

// Associates (trajectory_association.h), aligns if asked, and summarizes.
// Errors on invalid options, empty or unsorted input, no match, a degenerate
// alignment, or an RPE delta longer than the matched trajectory.
Result<TrajectoryErrorSummary> ComputeTrajectoryErrors(
    const Trajectory& estimate, const Trajectory& reference,
    const TrajectoryMetricsOptions& options = {});
// The same from an existing association (options.association is not used).
Result<TrajectoryErrorSummary> SummarizeTrajectoryErrors(const Association& association,
                                                         const TrajectoryMetricsOptions& options);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_TRAJECTORY_METRICS_H_
