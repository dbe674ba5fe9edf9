#include "groundline/core/metric_fields.h"
#include "groundline/core/angles.h"

#include <numbers>

namespace groundline::core {
namespace {

void AddCount(std::vector<MetricField>* fields, const char* key, const char* label,
              std::size_t value) {
  fields->push_back({key, label, static_cast<double>(value), true});
}

void Add(std::vector<MetricField>* fields, const char* key, const char* label, double value) {
  fields->push_back({key, label, value, false});
}

void AddStats(std::vector<MetricField>* fields, const std::string& prefix, const std::string& name,
              const std::string& unit, const ErrorStats& stats) {
  const std::pair<const char*, double> parts[] = {
      {"rmse", stats.rmse}, {"mean", stats.mean}, {"median", stats.median}, {"max", stats.max}};
  for (const auto& [what, value] : parts) {
    fields->push_back(
        {prefix + "_" + what + "_" + unit, name + " " + what + " [" + unit + "]", value, false});
  }
}

}  // namespace

std::vector<MetricField> MetricFields(const TrajectoryErrorSummary& s) {
  std::vector<MetricField> f;
  AddCount(&f, "n_matched", "matched poses", s.n_matched);
  AddCount(&f, "n_unmatched", "unmatched poses", s.n_unmatched);
  Add(&f, "ate_rmse_m", "ATE RMSE [m]", s.ate_m.rmse);
  Add(&f, "ate_mean_m", "ATE mean [m]", s.ate_m.mean);
  Add(&f, "ate_median_m", "ATE median [m]", s.ate_m.median);
  Add(&f, "ate_max_m", "ATE max [m]", s.ate_m.max);
  Add(&f, "along_rmse_m", "along-track RMSE [m]", s.along_rmse_m);
  Add(&f, "cross_rmse_m", "cross-track RMSE [m]", s.cross_rmse_m);
  Add(&f, "heading_rmse_deg", "heading RMSE [deg]", s.heading_rmse_deg);
  AddCount(&f, "n_tangent_from_heading", "tangent from heading", s.n_direction_from_heading);
  if (s.T_ref_est) {
    Add(&f, "align_x_m", "alignment x [m]", s.T_ref_est->x());
    Add(&f, "align_y_m", "alignment y [m]", s.T_ref_est->y());
    Add(&f, "align_yaw_deg", "alignment yaw [deg]", s.T_ref_est->yaw() * kRadToDeg);
  }
  if (s.nees) {
    AddCount(&f, "nees_n", "NEES poses", s.nees->n);
    AddCount(&f, "nees_n_invalid_cov", "invalid covariances", s.nees->n_invalid_covariance);
    Add(&f, "nees_mean", "NEES mean (3 expected)", s.nees->mean);
    Add(&f, "nees_in_band", "NEES in 95% band [share]", s.nees->in_band_share);
  }
  if (s.rpe) {
    if (s.rpe->options.unit == RpeDeltaUnit::kMetres) {
      Add(&f, "rpe_delta_m", "RPE delta [m]", s.rpe->options.delta);
    } else {
      AddCount(&f, "rpe_delta_frames", "RPE delta [frames]",
               static_cast<std::size_t>(s.rpe->options.delta));
    }
    AddCount(&f, "rpe_n", "RPE pairs", s.rpe->trans_m.n);
    AddStats(&f, "rpe_trans", "RPE trans", "m", s.rpe->trans_m);
    AddStats(&f, "rpe_rot", "RPE rot", "deg", s.rpe->rot_deg);
  }
  return f;
}

std::vector<MetricField> MetricFields(const RelationErrorSummary& s) {
  std::vector<MetricField> f;
  AddCount(&f, "rel_n", "relations used", s.n_used);
  AddCount(&f, "rel_n_skipped", "relations skipped", s.n_skipped);
  Add(&f, "rel_trans_mean_m", "relation trans mean [m]", s.trans_m.mean);
  Add(&f, "rel_trans_std_m", "relation trans std [m]", s.trans_m.std_dev);
  Add(&f, "rel_rot_mean_deg", "relation rot mean [deg]", s.rot_deg.mean);
  Add(&f, "rel_rot_std_deg", "relation rot std [deg]", s.rot_deg.std_dev);
  Add(&f, "rel_trans_max_m", "relation trans max [m]", s.trans_m.max);
  Add(&f, "rel_rot_max_deg", "relation rot max [deg]", s.rot_deg.max);
  return f;
}

std::vector<MetricField> MetricFields(const AisleExitSummary& s) {
  std::vector<MetricField> f;
  AddCount(&f, "aisle_exits_n", "aisle exits", s.n_exits);
  AddCount(&f, "aisle_exits_unmatched", "aisle exits unmatched", s.n_unmatched);
  Add(&f, "aisle_exit_rmse_m", "aisle exit error RMSE [m]", s.error_m.rmse);
  Add(&f, "aisle_exit_max_m", "aisle exit error max [m]", s.error_m.max);
  AddCount(&f, "aisle_exits_above_threshold", "aisle exits above threshold", s.n_above_threshold);
  return f;
}

}  // namespace groundline::core
