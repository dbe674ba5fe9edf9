// The named numbers of a metrics summary, in a fixed order: one list that
// both the JSON writer and the table printer of `groundline eval` use, so that
// the keys of EVAL.md are spelled in exactly one place. Keys carry their unit
// (_m, _deg; counts and ratios have none); labels are for people.
//
// The core stays free of a JSON library: tools/ turns these into JSON.
#ifndef GROUNDLINE_CORE_METRIC_FIELDS_H_
#define GROUNDLINE_CORE_METRIC_FIELDS_H_

#include <string>
#include <vector>

#include "groundline/core/aisle_exits.h"
#include "groundline/core/relation_metrics.h"
#include "groundline/core/trajectory_metrics.h"

namespace groundline::core {

struct MetricField {
  std::string key;    // e.g. "ate_rmse_m"
  std::string label;  // e.g. "ATE RMSE [m]"
  double value = 0.0;
  bool is_count = false;  // a non-negative integer
};

// Always: n_matched, n_unmatched, ate_rmse_m, ate_mean_m, ate_median_m,
// ate_max_m, along_rmse_m, cross_rmse_m, heading_rmse_deg, n_tangent_from_heading.
// With alignment: align_x_m, align_y_m, align_yaw_deg (T_ref_est).
// With covariances: nees_n, nees_n_invalid_cov, nees_mean, nees_in_band (a share in [0, 1]).
// With RPE: rpe_delta_m or rpe_delta_frames, rpe_n, rpe_trans_{rmse,mean,median,max}_m,
// rpe_rot_{rmse,mean,median,max}_deg.
std::vector<MetricField> MetricFields(const TrajectoryErrorSummary& summary);

// rel_n, rel_n_skipped, rel_trans_mean_m, rel_trans_std_m, rel_rot_mean_deg,
// rel_rot_std_deg (population std), rel_trans_max_m, rel_rot_max_deg.
std::vector<MetricField> MetricFields(const RelationErrorSummary& summary);

// aisle_exits_n, aisle_exits_unmatched, aisle_exit_rmse_m, aisle_exit_max_m,
// aisle_exits_above_threshold.
std::vector<MetricField> MetricFields(const AisleExitSummary& summary);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_METRIC_FIELDS_H_
