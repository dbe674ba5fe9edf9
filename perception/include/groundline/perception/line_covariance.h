// The covariance model of extracted floor lines: pixel noise in the camera
// image, carried to the floor through the Jacobian of the inverse
// (lens-model) homography, then to the line through the point-to-line
// Jacobians (seed paper eq. 47).
//
// Model. A ridge centre found in the BEV is a floor point x_i (base_link,
// metres) seen at a camera pixel u_i. Its pixel position is uncertain by
// isotropic noise of standard deviation sigma_px; on the floor that becomes
//
//   Sigma_i = sigma_px^2 J_i J_i^T,   J_i = d(floor)/d(pixel) at u_i  (m/px),
//
// the Jacobian of the back-projection (calibration::FloorProjection, or
// BackProjectPixel for an ideal homography). Only the component across the
// line moves a line fit: sigma_perp,i^2 = n^T Sigma_i n. The line is the
// weighted total-least-squares fit (FitLineTls) with weights 1 / sigma_perp,i^2,
// and its covariance follows from there (hesse_line.h). For two points this is
// exactly J_1 Sigma_1 J_1^T + J_2 Sigma_2 J_2^T with the endpoint-to-line
// Jacobians of LineFromPoints.
//
// Correlated samples. Ridge centres sampled every cell along a line filtered
// with a Gaussian of scale sigma are not independent: their errors are
// correlated over about 2 sqrt(pi) sigma cells. correlation_samples multiplies
// the independent-sample covariance by that number of samples per independent
// one (>= 1; 1 for independent points).
//
// Functions are pure and thread-safe.
#ifndef GROUNDLINE_PERCEPTION_LINE_COVARIANCE_H_
#define GROUNDLINE_PERCEPTION_LINE_COVARIANCE_H_

#include <Eigen/Core>
#include <span>

#include "groundline/calibration/floor_projection.h"
#include "groundline/core/status.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::perception {

// Sigma_floor = sigma_px^2 J J^T (m^2) of a floor point whose pixel has
// isotropic noise sigma_px; J_floor_pixel is d(x, y)/d(u, v), m/px.
Eigen::Matrix2d FloorPointCovariance(const Eigen::Matrix2d& J_floor_pixel, double sigma_px);

// A line and its covariance of (rho_m, alpha_rad).
struct LineEstimate {
  HesseLine line;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
};

// The line through two floor endpoints with covariances S1, S2 (m^2):
// covariance = J1 S1 J1^T + J2 S2 J2^T, J_k = d(rho, alpha)/d(p_k) from
// LineFromPoints. Fails when the points coincide.
core::Result<LineEstimate> LineFromEndpoints(const Eigen::Vector2d& p1_m, const Eigen::Matrix2d& S1,
                                             const Eigen::Vector2d& p2_m,
                                             const Eigen::Matrix2d& S2);

// The floor line through the floor points of two camera pixels, via the
// camera's back-projection. J_line_px1, J_line_px2: d(rho, alpha)/d(u, v)
// (2x2 each) = J_line_point * J_floor_pixel. Fails when a pixel does not see
// the floor or the points coincide.
core::Result<HesseLine> LineFromPixels(const calibration::FloorProjection& projection,
                                       const Eigen::Vector2d& pixel1, const Eigen::Vector2d& pixel2,
                                       Eigen::Matrix2d* J_line_px1 = nullptr,
                                       Eigen::Matrix2d* J_line_px2 = nullptr);

// The weighted TLS line through floor points whose pixel noise is sigma_px,
// J_floor_pixel[i] the back-projection Jacobian at point i (one per point).
// The covariance is that of FitLineTls with per-point perpendicular variances
// sigma_px^2 n^T J_i J_i^T n (n from an unweighted first fit), multiplied by
// correlation_samples (>= 1). Fails as FitLineTls does, or on a bad argument.
core::Result<LineFit> FitLineWithPixelNoise(std::span<const Eigen::Vector2d> points_m,
                                            std::span<const Eigen::Matrix2d> J_floor_pixel,
                                            double sigma_px, double correlation_samples = 1.0);

// The covariance model of extracted lines, whose noise is measured on each
// line (docs/perception.md, "Covariance model"). The centres' noise depends on
// the marking's contrast, the image noise, the blur and the width of the
// ridge, all of which vary per line; their joint effect is the scatter of the
// line's own centres about its fit, expressed in pixels:
//
//   lambda^2 = (1/N) sum_i d_i^2 / (n^T J_i J_i^T n) * N_eff / (N_eff - 2),
//   N_eff = N / scatter_correlation_samples  (independent samples for the
//           scatter; clamped >= 3; 0: correlation_samples),
//
// (d_i: residuals of the weighted fit, the factor undoes the fit's absorption
// of two degrees of freedom). sigma_px^2 = max(lambda^2, min_sigma_px^2), and
//
//   C = correlation_samples * C_tls(sigma_px) + C_floor,
//   C_floor = rho_floor_m^2 [1 0; 0 0] + alpha_floor_rad^2 [s0^2 s0; s0 1],
//
// where the floor holds what the scatter cannot show: errors constant along
// a line (the sub-cell phase of a line running along the BEV grid, edge
// asymmetry of wide bars, a stain or scuff pulling a stretch of it). It is an
// offset of the line (rho_floor_m) and a turn about the centroid c of its
// points (alpha_floor_rad), s0 = Direction() . c, which is how such errors
// move a line; a floor diag(rho^2, alpha^2) would turn it about the foot of
// the origin instead, which for a line 1-2.5 m ahead adds 1.7 alpha_floor of
// sideways play at its middle. The two correlation numbers differ when the
// centres' errors are band-pass (positive correlation over a few cells, a
// negative lobe beyond): the scatter then has fewer degrees of freedom than
// the mean of the errors has independent terms.
struct LineNoiseModel {
  double min_sigma_px = 0.3;
  double correlation_samples = 1.0;          // >= 1
  double scatter_correlation_samples = 0.0;  // >= 1, or 0: correlation_samples
  double rho_floor_m = 0.0;
  double alpha_floor_rad = 0.0;
  // false: the floor is diag(rho_floor_m^2, alpha_floor_rad^2), a turn about
  // the foot of the origin (the model before the fourth round, which the
  // localization smoother's line covariance was tuned with).
  bool floor_about_centroid = true;

  core::Status Validate() const;
};

// FitLineWithPixelNoise with the noise of the line measured as above.
// *sigma_px (if not null) receives the sigma_px used. Fails as
// FitLineWithPixelNoise does, or for fewer than 3 points.
core::Result<LineFit> FitLineWithMeasuredNoise(std::span<const Eigen::Vector2d> points_m,
                                               std::span<const Eigen::Matrix2d> J_floor_pixel,
                                               const LineNoiseModel& model,
                                               double* sigma_px = nullptr);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_LINE_COVARIANCE_H_
