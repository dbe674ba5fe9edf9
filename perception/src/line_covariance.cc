// Pixel noise -> floor -> line covariance (line_covariance.h).
#include "groundline/perception/line_covariance.h"

#include <cmath>
#include <string>
#include <vector>

namespace groundline::perception {

Eigen::Matrix2d FloorPointCovariance(const Eigen::Matrix2d& J_floor_pixel, double sigma_px) {
  return sigma_px * sigma_px * J_floor_pixel * J_floor_pixel.transpose();
}

core::Result<LineEstimate> LineFromEndpoints(const Eigen::Vector2d& p1_m, const Eigen::Matrix2d& S1,
                                             const Eigen::Vector2d& p2_m,
                                             const Eigen::Matrix2d& S2) {
  Eigen::Matrix2d J1, J2;
  core::Result<HesseLine> line = LineFromPoints(p1_m, p2_m, &J1, &J2);
  if (!line.ok()) return core::Status::Error(line.message());
  LineEstimate estimate;
  estimate.line = *line;
  estimate.covariance = J1 * S1 * J1.transpose() + J2 * S2 * J2.transpose();
  return estimate;
}

core::Result<HesseLine> LineFromPixels(const calibration::FloorProjection& projection,
                                       const Eigen::Vector2d& pixel1, const Eigen::Vector2d& pixel2,
                                       Eigen::Matrix2d* J_line_px1, Eigen::Matrix2d* J_line_px2) {
  Eigen::Matrix2d J_floor_px1, J_floor_px2;
  core::Result<Eigen::Vector2d> p1 = projection.FloorPointOfPixel(pixel1, &J_floor_px1);
  if (!p1.ok()) return core::Status::Error(p1.message());
  core::Result<Eigen::Vector2d> p2 = projection.FloorPointOfPixel(pixel2, &J_floor_px2);
  if (!p2.ok()) return core::Status::Error(p2.message());
  Eigen::Matrix2d J_line_p1, J_line_p2;
  core::Result<HesseLine> line = LineFromPoints(*p1, *p2, &J_line_p1, &J_line_p2);
  if (!line.ok()) return line;
  if (J_line_px1 != nullptr) *J_line_px1 = J_line_p1 * J_floor_px1;
  if (J_line_px2 != nullptr) *J_line_px2 = J_line_p2 * J_floor_px2;
  return line;
}

core::Result<LineFit> FitLineWithPixelNoise(std::span<const Eigen::Vector2d> points_m,
                                            std::span<const Eigen::Matrix2d> J_floor_pixel,
                                            double sigma_px, double correlation_samples) {
  if (J_floor_pixel.size() != points_m.size()) {
    return core::Status::Error("FitLineWithPixelNoise: got " +
                               std::to_string(J_floor_pixel.size()) + " Jacobians for " +
                               std::to_string(points_m.size()) + " points");
  }
  if (!(correlation_samples >= 1.0) || !std::isfinite(correlation_samples)) {
    return core::Status::Error("FitLineWithPixelNoise: correlation_samples must be >= 1, got " +
                               std::to_string(correlation_samples));
  }
  core::Result<LineFit> first = FitLineTls(points_m, {}, 1.0);
  if (!first.ok()) return first;
  const Eigen::Vector2d n = first->line.Normal();
  std::vector<double> perpendicular_variance(points_m.size());
  double mean_variance = 0.0;
  for (size_t i = 0; i < points_m.size(); ++i) {
    const Eigen::Vector2d Jt_n = J_floor_pixel[i].transpose() * n;
    perpendicular_variance[i] = sigma_px * sigma_px * Jt_n.squaredNorm();
    if (!(perpendicular_variance[i] > 0.0)) {
      return core::Status::Error("FitLineWithPixelNoise: point " + std::to_string(i) +
                                 " has no noise across the line (singular Jacobian)");
    }
    mean_variance += perpendicular_variance[i];
  }
  mean_variance /= static_cast<double>(points_m.size());
  std::vector<double> weights(points_m.size());
  for (size_t i = 0; i < points_m.size(); ++i) {
    weights[i] = mean_variance / perpendicular_variance[i];
  }
  core::Result<LineFit> fit = FitLineTls(points_m, weights, std::sqrt(mean_variance));
  if (fit.ok()) fit->covariance *= correlation_samples;
  return fit;
}

core::Status LineNoiseModel::Validate() const {
  auto bad = [](const std::string& field, const std::string& expected) {
    return core::Status::Error("LineNoiseModel." + field + ": expected " + expected);
  };
  if (!(min_sigma_px > 0.0) || !std::isfinite(min_sigma_px)) {
    return bad("min_sigma_px", "a number > 0");
  }
  if (!(correlation_samples >= 1.0) || !std::isfinite(correlation_samples)) {
    return bad("correlation_samples", "a number >= 1");
  }
  if (!(scatter_correlation_samples == 0.0 || scatter_correlation_samples >= 1.0) ||
      !std::isfinite(scatter_correlation_samples)) {
    return bad("scatter_correlation_samples", "0 or a number >= 1");
  }
  if (!(rho_floor_m >= 0.0) || !std::isfinite(rho_floor_m)) {
    return bad("rho_floor_m", "a number >= 0");
  }
  if (!(alpha_floor_rad >= 0.0) || !std::isfinite(alpha_floor_rad)) {
    return bad("alpha_floor_rad", "a number >= 0");
  }
  return core::Status::Ok();
}

core::Result<LineFit> FitLineWithMeasuredNoise(std::span<const Eigen::Vector2d> points_m,
                                               std::span<const Eigen::Matrix2d> J_floor_pixel,
                                               const LineNoiseModel& model, double* sigma_px) {
  if (core::Status s = model.Validate(); !s.ok()) return s;
  if (points_m.size() < 3) {
    return core::Status::Error("FitLineWithMeasuredNoise: need at least 3 points, got " +
                               std::to_string(points_m.size()));
  }
  core::Result<LineFit> fit = FitLineWithPixelNoise(points_m, J_floor_pixel, 1.0, 1.0);
  if (!fit.ok()) return fit;
  const Eigen::Vector2d n = fit->line.Normal();
  double sum = 0.0;
  for (size_t i = 0; i < points_m.size(); ++i) {
    const double d = SignedDistance(fit->line, points_m[i]);
    sum += d * d / (J_floor_pixel[i].transpose() * n).squaredNorm();
  }
  const double count = static_cast<double>(points_m.size());
  const double scatter_correlation = model.scatter_correlation_samples > 0.0
                                         ? model.scatter_correlation_samples
                                         : model.correlation_samples;
  const double independent = std::max(3.0, count / scatter_correlation);
  const double lambda2 = sum / count * independent / (independent - 2.0);
  const double sigma2 = std::max(lambda2, model.min_sigma_px * model.min_sigma_px);
  fit->covariance *= model.correlation_samples * sigma2;
  // The floors: an offset and a turn about the points' centroid c. A turn by
  // e there moves (rho, alpha) by (s0 e, e), s0 = Direction() . c.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points_m) centroid += p;
  centroid /= count;
  const double s0 = model.floor_about_centroid ? fit->line.Direction().dot(centroid) : 0.0;
  const double offset2 = model.rho_floor_m * model.rho_floor_m;
  const double turn2 = model.alpha_floor_rad * model.alpha_floor_rad;
  fit->covariance(0, 0) += offset2 + s0 * s0 * turn2;
  fit->covariance(0, 1) += s0 * turn2;
  fit->covariance(1, 0) += s0 * turn2;
  fit->covariance(1, 1) += turn2;
  if (sigma_px != nullptr) *sigma_px = std::sqrt(sigma2);
  return fit;
}

}  // namespace groundline::perception
