#include "groundline/core/trajectory_metrics.h"
#include "groundline/core/angles.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace groundline::core {
namespace {

double Rms(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  double sum_sq = 0.0;
  for (double v : values) sum_sq += v * v;
  return std::sqrt(sum_sq / static_cast<double>(values.size()));
}

// e^T Sigma^-1 e, or nullopt if Sigma is not finite, symmetric and positive definite.
std::optional<double> Nees(const Vector3& error, const Matrix3& covariance) {
  if (!covariance.allFinite()) return std::nullopt;
  const double scale = std::max(covariance.cwiseAbs().maxCoeff(), 1e-300);
  if ((covariance - covariance.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    return std::nullopt;
  }
  const Eigen::LLT<Matrix3> llt(covariance);
  if (llt.info() != Eigen::Success) return std::nullopt;
  const double nees = error.dot(llt.solve(error));
  if (!std::isfinite(nees) || nees < 0.0) return std::nullopt;
  return nees;
}

}  // namespace

ErrorStats ComputeErrorStats(std::vector<double> values) {
  ErrorStats stats;
  stats.n = values.size();
  if (values.empty()) return stats;
  const double n = static_cast<double>(values.size());
  double sum = 0.0;
  double sum_sq = 0.0;
  double max = values.front();
  for (double v : values) {
    sum += v;
    sum_sq += v * v;
    max = std::max(max, v);
  }
  stats.mean = sum / n;
  stats.rmse = std::sqrt(sum_sq / n);
  double sum_dev_sq = 0.0;
  for (double v : values) sum_dev_sq += (v - stats.mean) * (v - stats.mean);
  stats.std_dev = std::sqrt(sum_dev_sq / n);
  stats.max = max;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  stats.median = values[mid];
  if (values.size() % 2 == 0) {
    const double below =
        *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid));
    stats.median = 0.5 * (stats.median + below);
  }
  return stats;
}

Result<SE2> AlignSE2(const std::vector<Vector2>& p_est_m, const std::vector<Vector2>& p_ref_m) {
  if (p_est_m.size() != p_ref_m.size()) {
    return Status::Error("alignment: " + std::to_string(p_est_m.size()) +
                         " estimate positions but " + std::to_string(p_ref_m.size()) +
                         " reference positions");
  }
  if (p_est_m.size() < 2) {
    return Status::Error("alignment needs at least 2 matched poses, got " +
                         std::to_string(p_est_m.size()));
  }
  const double n = static_cast<double>(p_est_m.size());
  Vector2 mean_est = Vector2::Zero();
  Vector2 mean_ref = Vector2::Zero();
  for (std::size_t i = 0; i < p_est_m.size(); ++i) {
    mean_est += p_est_m[i];
    mean_ref += p_ref_m[i];
  }
  mean_est /= n;
  mean_ref /= n;
  double dot = 0.0;
  double cross = 0.0;
  double spread_sq = 0.0;
  for (std::size_t i = 0; i < p_est_m.size(); ++i) {
    const Vector2 a = p_est_m[i] - mean_est;
    const Vector2 b = p_ref_m[i] - mean_ref;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
    spread_sq += a.squaredNorm() + b.squaredNorm();
  }
  // Coincident points (a stationary trajectory) leave the rotation free.
  if (std::hypot(dot, cross) <= 1e-12 * std::max(spread_sq, 1e-300) || spread_sq < 1e-18 * n) {
    return Status::Error(
        "alignment is undetermined: the matched positions do not spread out "
        "(a stationary trajectory?); evaluate without alignment");
  }
  const double yaw_rad = std::atan2(cross, dot);
  const SE2 rotation(0.0, 0.0, yaw_rad);
  return SE2(mean_ref - rotation.Act(mean_est), yaw_rad);
}

std::vector<PoseError> ComputePoseErrors(const std::vector<PosePair>& pairs, const SE2& T_ref_est) {
  std::vector<PoseError> errors;
  errors.reserve(pairs.size());
  for (const PosePair& pair : pairs) {
    const SE2 est = T_ref_est * pair.T_map_est;
    PoseError error;
    error.stamp_s = pair.stamp_s;
    error.position_error_map_m = est.translation() - pair.T_map_ref.translation();
    const Vector2& u = pair.ref_direction_map;
    error.along_m = error.position_error_map_m.dot(u);
    error.cross_m = error.position_error_map_m.dot(Vector2(-u.y(), u.x()));
    error.heading_error_rad = WrapAngle(est.yaw() - pair.T_map_ref.yaw());
    if (pair.est_covariance) error.nees = Nees(pair.T_map_ref.Minus(est), *pair.est_covariance);
    errors.push_back(error);
  }
  return errors;
}

Status TrajectoryMetricsOptions::Validate() const {
  if (Status s = association.Validate(); !s.ok()) return s;
  if (rpe) return rpe->Validate();
  return Status::Ok();
}

Result<TrajectoryErrorSummary> SummarizeTrajectoryErrors(const Association& association,
                                                         const TrajectoryMetricsOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  if (association.pairs.empty()) return Status::Error("no matched poses to evaluate");
  TrajectoryErrorSummary summary;
  summary.n_matched = association.pairs.size();
  summary.n_unmatched = association.n_unmatched;
  summary.association_method = options.association.method;

  SE2 T_ref_est;
  if (options.align) {
    std::vector<Vector2> p_est_m, p_ref_m;
    for (const PosePair& pair : association.pairs) {
      p_est_m.push_back(pair.T_map_est.translation());
      p_ref_m.push_back(pair.T_map_ref.translation());
    }
    Result<SE2> alignment = AlignSE2(p_est_m, p_ref_m);
    if (!alignment.ok()) return alignment.status();
    T_ref_est = *alignment;
    summary.T_ref_est = T_ref_est;
  }

  const std::vector<PoseError> errors = ComputePoseErrors(association.pairs, T_ref_est);
  std::vector<double> ate_m, along_m, cross_m, heading_deg, nees;
  std::size_t n_with_covariance = 0;
  for (std::size_t i = 0; i < errors.size(); ++i) {
    ate_m.push_back(errors[i].position_error_map_m.norm());
    along_m.push_back(errors[i].along_m);
    cross_m.push_back(errors[i].cross_m);
    heading_deg.push_back(errors[i].heading_error_rad * kRadToDeg);
    if (association.pairs[i].direction_from_heading) ++summary.n_direction_from_heading;
    if (association.pairs[i].est_covariance) ++n_with_covariance;
    if (errors[i].nees) nees.push_back(*errors[i].nees);
  }
  summary.ate_m = ComputeErrorStats(std::move(ate_m));
  summary.along_rmse_m = Rms(along_m);
  summary.cross_rmse_m = Rms(cross_m);
  summary.heading_rmse_deg = Rms(heading_deg);

  if (n_with_covariance > 0) {
    NeesSummary nees_summary;
    nees_summary.n = nees.size();
    nees_summary.n_invalid_covariance = n_with_covariance - nees.size();
    std::size_t in_band = 0;
    for (double v : nees) {
      if (v >= kNeesLower95Dof3 && v <= kNeesUpper95Dof3) ++in_band;
    }
    if (!nees.empty()) {
      nees_summary.mean = ComputeErrorStats(nees).mean;
      nees_summary.in_band_share = static_cast<double>(in_band) / static_cast<double>(nees.size());
    }
    summary.nees = nees_summary;
  }

  if (options.rpe) {
    Result<RpeSummary> rpe = ComputeRpe(association.pairs, *options.rpe);
    if (!rpe.ok()) return rpe.status();
    summary.rpe = *rpe;
  }
  return summary;
}

Result<TrajectoryErrorSummary> ComputeTrajectoryErrors(const Trajectory& estimate,
                                                       const Trajectory& reference,
                                                       const TrajectoryMetricsOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  Result<Association> association = AssociateByStamp(estimate, reference, options.association);
  if (!association.ok()) return association.status();
  return SummarizeTrajectoryErrors(*association, options);
}

}  // namespace groundline::core
