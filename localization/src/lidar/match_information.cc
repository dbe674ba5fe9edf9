#include "groundline/localization/lidar/match_information.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace groundline::localization::lidar {

core::Status MatchInformationOptions::Validate() const {
  if (!(point_sigma_m > 0.0 && max_independent_points > 0.0)) {
    return core::Status::Error("point_sigma_m and max_independent_points must be > 0");
  }
  if (!(min_eigenvalue_ratio >= 0.0 && min_eigenvalue_ratio < 1.0 && min_eigenvalue >= 0.0)) {
    return core::Status::Error("need 0 <= min_eigenvalue_ratio < 1 and min_eigenvalue >= 0");
  }
  return core::Status::Ok();
}

MatchInformation ComputeMatchInformation(const std::vector<ScanPoint>& points,
                                         const MatchInformationOptions& options) {
  MatchInformation out;
  core::Matrix3 sum = core::Matrix3::Zero();
  double range2_sum = 0.0;
  for (const ScanPoint& sp : points) {
    if (!sp.has_normal()) continue;
    const core::Vector2& p = sp.point_m;
    const Eigen::RowVector3d J(sp.normal.x(), sp.normal.y(),
                               sp.normal.x() * -p.y() + sp.normal.y() * p.x());
    sum += J.transpose() * J;
    range2_sum += p.squaredNorm();
    ++out.points_with_normal;
  }
  if (out.points_with_normal == 0) {
    out.degenerate = true;
    out.weakest_direction = core::Vector3::UnitX();
    return out;
  }
  const double n = out.points_with_normal;
  const double scale = std::min(1.0, options.max_independent_points / n);
  out.information = scale * sum / (options.point_sigma_m * options.point_sigma_m);
  const double length_m = std::max(1.0, std::sqrt(range2_sum / n));
  const core::Vector3 d(1.0, 1.0, 1.0 / length_m);
  const core::Matrix3 scaled = d.asDiagonal() * out.information * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<core::Matrix3> eig(scaled);
  out.scaled_eigenvalues = eig.eigenvalues();
  const double threshold =
      std::max(options.min_eigenvalue, options.min_eigenvalue_ratio * eig.eigenvalues()(2));
  core::Matrix3 sqrt_scaled = core::Matrix3::Zero();
  for (int k = 0; k < 3; ++k) {
    const double lambda = eig.eigenvalues()(k);
    if (lambda < threshold) continue;
    ++out.rank;
    sqrt_scaled.row(k) = std::sqrt(lambda) * eig.eigenvectors().col(k).transpose();
  }
  // Lambda = D^-1 (D Lambda D) D^-1, so S = S_scaled D^-1.
  out.sqrt_information = sqrt_scaled * d.cwiseInverse().asDiagonal();
  out.degenerate = out.rank < 3;
  const core::Vector3 weakest = d.asDiagonal() * eig.eigenvectors().col(0);
  out.weakest_direction = weakest.normalized();
  return out;
}

}  // namespace groundline::localization::lidar
