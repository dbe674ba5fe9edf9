// FitLineTls of hesse_line.h.
#include "groundline/perception/hesse_line.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

namespace groundline::perception {
namespace {

// The weighted along-line spread sqrt(S / W) below which the points are taken
// to be one point (no direction).
constexpr double kMinSpreadM = 1e-9;

core::Status FitError(const std::string& what) {
  return core::Status::Error("FitLineTls: " + what);
}

}  // namespace

core::Result<LineFit> FitLineTls(std::span<const Eigen::Vector2d> points_m,
                                 std::span<const double> weights, double sigma_m) {
  if (points_m.size() < 2) {
    return FitError("need at least 2 points, got " + std::to_string(points_m.size()));
  }
  if (!weights.empty() && weights.size() != points_m.size()) {
    return FitError("got " + std::to_string(weights.size()) + " weights for " +
                    std::to_string(points_m.size()) + " points (expected none or one per point)");
  }
  if (!(sigma_m > 0.0) || !std::isfinite(sigma_m)) {
    return FitError("sigma_m must be a finite number > 0, got " + std::to_string(sigma_m));
  }
  double weight_sum = 0.0;
  Eigen::Vector2d weighted_sum = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < points_m.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (!(w > 0.0) || !std::isfinite(w)) {
      return FitError("weight " + std::to_string(i) + " must be finite and > 0, got " +
                      std::to_string(w));
    }
    if (!points_m[i].allFinite()) {
      return FitError("point " + std::to_string(i) + " is not finite");
    }
    weight_sum += w;
    weighted_sum += w * points_m[i];
  }
  const Eigen::Vector2d centroid = weighted_sum / weight_sum;
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (size_t i = 0; i < points_m.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    const Eigen::Vector2d r = points_m[i] - centroid;
    scatter += w * r * r.transpose();
  }
  // Eigenvalues ascending: the smaller one is sum w d^2 (its vector is the
  // normal), the larger one S = sum w s^2 along the line.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
  const double along_spread = eigen.eigenvalues()(1);
  if (!(along_spread > kMinSpreadM * kMinSpreadM * weight_sum)) {
    return FitError("the " + std::to_string(points_m.size()) +
                    " points coincide; they do not determine a direction");
  }
  const Eigen::Vector2d normal = eigen.eigenvectors().col(0);
  LineFit fit;
  fit.line = NormalizeLine(normal.dot(centroid), std::atan2(normal.y(), normal.x()));
  // Summed directly: the small eigenvalue carries an error of eps * S.
  double weighted_square_sum = 0.0;
  for (size_t i = 0; i < points_m.size(); ++i) {
    const double d = normal.dot(points_m[i] - centroid);
    weighted_square_sum += (weights.empty() ? 1.0 : weights[i]) * d * d;
  }
  fit.rms_residual_m = std::sqrt(weighted_square_sum / weight_sum);

  // Offset a (along n, at the centroid) and slope (d alpha) are uncorrelated
  // because sum w s = 0 about the weighted centroid; rho = n(alpha) . (c + a n)
  // gives d rho = a + s0 d alpha.
  const double sigma2 = sigma_m * sigma_m;
  const double var_alpha = sigma2 / along_spread;
  const double s0 = fit.line.Direction().dot(centroid);
  fit.covariance << sigma2 / weight_sum + s0 * s0 * var_alpha, s0 * var_alpha,  //
      s0 * var_alpha, var_alpha;
  return fit;
}

}  // namespace groundline::perception
