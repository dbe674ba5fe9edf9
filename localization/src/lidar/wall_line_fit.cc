#include <Eigen/LU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>
#include <vector>

#include "groundline/localization/lidar/wall_lines.h"

namespace groundline::localization::lidar {

Eigen::Matrix<double, 2, Eigen::Dynamic> WeightedTlsJacobian(
    const perception::HesseLine& line, std::span<const Eigen::Vector2d> points_m,
    std::span<const double> weights) {
  assert(weights.empty() || weights.size() == points_m.size());
  const Eigen::Vector2d n = line.Normal();
  const Eigen::Vector2d d = line.Direction();
  const auto weight = [&](std::size_t i) { return weights.empty() ? 1.0 : weights[i]; };
  double W = 0.0, sum_wt = 0.0, a22 = 0.0;
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    const double w = weight(i);
    const double np = n.dot(points_m[i]);
    const double e = np - line.rho_m;
    const double t = d.dot(points_m[i]);
    W += w;
    sum_wt += w * t;
    a22 += w * (t * t - e * np);
  }
  Eigen::Matrix2d A;
  A << -W, sum_wt, -sum_wt, a22;
  const Eigen::Matrix2d A_inv = A.inverse();
  Eigen::Matrix<double, 2, Eigen::Dynamic> J(2, 2 * points_m.size());
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    const double w = weight(i);
    const double e = n.dot(points_m[i]) - line.rho_m;
    const double t = d.dot(points_m[i]);
    Eigen::Matrix2d B;
    B.row(0) = w * n.transpose();
    B.row(1) = w * (t * n + e * d).transpose();
    J.middleCols<2>(2 * static_cast<Eigen::Index>(i)) = -A_inv * B;
  }
  return J;
}

core::Result<WallLineFit> FitWallLine(std::span<const RangePoint> points, double range_sigma_m,
                                      double face_sigma_m) {
  if (!(range_sigma_m > 0.0) || !(face_sigma_m >= 0.0)) {
    return core::Status::Error(
        "FitWallLine: range_sigma_m must be > 0 and face_sigma_m >= 0, got " +
        std::to_string(range_sigma_m) + ", " + std::to_string(face_sigma_m));
  }
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(points.size());
  for (const RangePoint& p : points) xy.push_back(p.point_m);
  const auto covariance_of = [&](const RangePoint& p) -> Eigen::Matrix2d {
    return range_sigma_m * range_sigma_m * p.ray_direction * p.ray_direction.transpose() +
           face_sigma_m * face_sigma_m * Eigen::Matrix2d::Identity();
  };
  // Unweighted first, then weighted by the orthogonal variance of each point
  // about that line (twice: the weights hardly change the normal).
  core::Result<perception::LineFit> fit = perception::FitLineTls(xy, {}, 1.0);
  if (!fit.ok()) return core::Status::Error("FitWallLine: " + fit.message());
  std::vector<double> weights(points.size());
  for (int round = 0; round < 2; ++round) {
    const Eigen::Vector2d n = fit->line.Normal();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double variance = n.dot(covariance_of(points[i]) * n);
      weights[i] = 1.0 / std::max(variance, 1e-12);
    }
    fit = perception::FitLineTls(xy, weights, 1.0);
    if (!fit.ok()) return core::Status::Error("FitWallLine: " + fit.message());
  }
  const Eigen::Matrix<double, 2, Eigen::Dynamic> J = WeightedTlsJacobian(fit->line, xy, weights);
  WallLineFit out;
  out.line = fit->line;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Matrix2d Ji = J.middleCols<2>(2 * static_cast<Eigen::Index>(i));
    out.covariance += Ji * covariance_of(points[i]) * Ji.transpose();
  }
  // rms of the orthogonal residuals in metres, weighted (FitLineTls' with w).
  double sw = 0.0, swd2 = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double e = perception::SignedDistance(fit->line, xy[i]);
    sw += weights[i];
    swd2 += weights[i] * e * e;
  }
  out.rms_residual_m = std::sqrt(swd2 / sw);
  return out;
}

}  // namespace groundline::localization::lidar
