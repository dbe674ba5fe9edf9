// The relation error of Kuemmerle et al. 2009, "On measuring the accuracy of
// SLAM algorithms" (Autonomous Robots 27(4)), eq. (2) with the translational
// and rotational parts reported separately, as on the Freiburg SLAM
// evaluation pages (see docs/metrics.md and shared/data/README.md).
//
// For each relation (t1, t2, delta_ref) with delta_ref = T_w_1^-1 T_w_2:
// - T_est_1, T_est_2 are the estimate poses whose stamps are nearest t1 and t2,
//   each within max_dt_s (else the relation is skipped and counted);
// - delta_est = T_est_1^-1 * T_est_2;
// - E = delta_ref^-1 * delta_est (the estimated relative pose seen from the
//   reference one); translational error |t(E)| [m], rotational |yaw(E)| [deg].
//   |t(E)| = |t(delta_est) - t(delta_ref)| since a rotation keeps the norm, so
//   the order of E (or E^-1) does not change either figure.
// Reported: mean and *population* standard deviation (divide by n) of each.
// With the raw odometry inside each FLASER line this reproduces the published
// figures to every printed digit (ACES 0.549 +- 2.674 m / 2.33 +- 6.50 deg,
// MIT CSAIL 1.682 +- 5.292 m / 5.07 +- 8.24 deg); the sample std does not.
//
// Pure and thread-safe.
#ifndef GROUNDLINE_CORE_RELATION_METRICS_H_
#define GROUNDLINE_CORE_RELATION_METRICS_H_

#include <cstddef>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/core/trajectory_metrics.h"

namespace groundline::core {

struct RelationMetricsOptions {
  // Largest |t_est - t_relation| for the pose nearest a relation stamp [s].
  double max_dt_s = 0.01;
  Status Validate() const;
};

struct RelationError {
  double t1_s = 0.0;
  double t2_s = 0.0;
  double trans_m = 0.0;
  double rot_rad = 0.0;  // |yaw(E)|, in [0, pi]
};

struct RelationErrorSummary {
  std::size_t n_used = 0;
  std::size_t n_skipped = 0;  // no estimate pose within max_dt_s of t1 or t2
  ErrorStats trans_m;         // .mean and .std_dev are the published figures
  ErrorStats rot_deg;
};

// The error of each relation that has estimate poses at both ends (in input
// order); the count of skipped ones in *n_skipped (may be null).
// `estimate` must be sorted by stamp (checked: error otherwise).
Result<std::vector<RelationError>> ComputeRelationErrorList(const Trajectory& estimate,
                                                            const std::vector<Relation>& relations,
                                                            const RelationMetricsOptions& options,
                                                            std::size_t* n_skipped = nullptr);

// Errors on invalid options, an empty or unsorted estimate, no relations, or
// no relation with estimate poses at both ends (the message gives the spans).
Result<RelationErrorSummary> ComputeRelationErrors(const Trajectory& estimate,
                                                   const std::vector<Relation>& relations,
                                                   const RelationMetricsOptions& options = {});

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_RELATION_METRICS_H_
