// Floor lines in Hesse normal form, the parameterization of every ground line
// (measured in base_link, or a landmark in map):
//
//   x cos(alpha) + y sin(alpha) = rho,
//
// n = (cos alpha, sin alpha) is the unit normal and rho the distance of the line
// from the frame origin (metres, radians). Seed paper eqs. (41)-(42), (51)-(53).
//
// Normalization. A line has two signed descriptions, (rho, alpha) and
// (-rho, alpha + pi). The normalized one has rho >= 0 and alpha in (-pi, pi]:
// the normal points from the origin toward the line. A line through the origin
// (rho == 0 exactly) has no such direction; it is given the alpha in
// (-pi/2, pi/2]. Every function returns normalized lines; every function
// accepts lines in either description.
//
// Jacobians are optional outputs (nullptr skips them) with respect to the
// (rho, alpha) coordinates of lines, points in metres, and right
// perturbations T Exp(d), d = (dx, dy, dtheta), of core::SE2 poses. They are
// derivatives of the normalized output, so where a function flips a line
// (rho crossing 0) the rho row changes sign; compare lines with LineDifference,
// which is continuous across that flip.
//
// All functions are pure and thread-safe.
#ifndef GROUNDLINE_PERCEPTION_HESSE_LINE_H_
#define GROUNDLINE_PERCEPTION_HESSE_LINE_H_

#include <Eigen/Core>
#include <span>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::perception {

struct HesseLine {
  double rho_m = 0.0;
  double alpha_rad = 0.0;

  // The unit normal (cos alpha, sin alpha).
  Eigen::Vector2d Normal() const;
  // The unit direction along the line, the normal turned by +90 deg.
  Eigen::Vector2d Direction() const;
};

using Matrix23 = Eigen::Matrix<double, 2, 3>;

// The normalized description of the line (rho_m, alpha_rad) (see above).
HesseLine NormalizeLine(double rho_m, double alpha_rad);

// NormalizeLine for an estimate with a covariance of (rho_m, alpha_rad): where
// the description flips to (-rho, alpha + pi) the covariance's rho-alpha
// correlation changes sign with it (J = diag(-1, 1)); covariance is updated in
// place and may be null.
HesseLine NormalizeLine(double rho_m, double alpha_rad, Eigen::Matrix2d* covariance);

// True if rho >= 0, alpha in (-pi, pi], and alpha in (-pi/2, pi/2] when rho == 0.
bool IsNormalized(const HesseLine& line);

// The line through p1 and p2 (metres). Fails when the points are closer than
// 1e-9 m. J_line_p1 and J_line_p2 are d(rho, alpha)/d(p), 2x2 each; with them
// the line covariance is J1 S1 J1^T + J2 S2 J2^T (seed paper eq. 47).
core::Result<HesseLine> LineFromPoints(const Eigen::Vector2d& p1_m, const Eigen::Vector2d& p2_m,
                                       Eigen::Matrix2d* J_line_p1 = nullptr,
                                       Eigen::Matrix2d* J_line_p2 = nullptr);

// Signed distance of a point from the line, x cos(alpha) + y sin(alpha) - rho:
// positive on the side the normal points to (beyond the line, seen from the
// origin, for a normalized line with rho > 0).
double SignedDistance(const HesseLine& line, const Eigen::Vector2d& point_m,
                      Eigen::RowVector2d* J_d_line = nullptr,
                      Eigen::RowVector2d* J_d_point = nullptr);

// The line given in frame b expressed in frame a, for p_a = T_a_b * p_b:
//   alpha_a = alpha_b + theta,  rho_a = rho_b + n_a . t   (then normalized).
// J_la_T (2x3, right perturbation of T_a_b), J_la_lb (2x2).
HesseLine TransformLine(const core::SE2& T_a_b, const HesseLine& line_b, Matrix23* J_la_T = nullptr,
                        Eigen::Matrix2d* J_la_lb = nullptr);

// The inverse direction: the line given in frame a expressed in frame b,
//   alpha_b = alpha_a - theta,  rho_b = rho_a - n_a . t   (then normalized).
// With T_a_b = T_map_base this is the prediction of the ground-line factor: a
// map line seen from the vehicle (seed paper eqs. 51-52). J_lb_T (2x3, right
// perturbation of T_a_b) and J_lb_la (2x2).
HesseLine InverseTransformLine(const core::SE2& T_a_b, const HesseLine& line_a,
                               Matrix23* J_lb_T = nullptr, Eigen::Matrix2d* J_lb_la = nullptr);

// The residual between two lines, a - b = (rho_a - rho_b, wrap(alpha_a - alpha_b)),
// computed between the descriptions of a and b whose normals differ by at most
// 90 deg: if |wrap(alpha_a - alpha_b)| > pi/2, a is used as (-rho_a, alpha_a + pi).
// It is therefore zero for the same line in any description and continuous when
// a line passes through the origin. It jumps where the lines are perpendicular,
// far outside any association gate. The result is expressed in b's
// description, so swapping a and b negates it only when no flip was needed; the
// ground-line factor uses LineDifference(predicted, measured). J_r_a, J_r_b: 2x2.
Eigen::Vector2d LineDifference(const HesseLine& a, const HesseLine& b,
                               Eigen::Matrix2d* J_r_a = nullptr, Eigen::Matrix2d* J_r_b = nullptr);

// A covariance of a's (rho, alpha) expressed in the description
// LineDifference(a, b) compares a in: J C J^T with J = J_r_a (diag(+-1, 1)),
// i.e. the rho-alpha correlation changes sign where a was flipped. Use it to
// add a's covariance to b's, or to weigh the difference.
Eigen::Matrix2d CovarianceInDescriptionOf(const HesseLine& a, const HesseLine& b,
                                          const Eigen::Matrix2d& covariance_a);

// The error of an estimate against the truth, estimate - truth, expressed in
// the estimate's description (the truth is flipped to (-rho, alpha + pi) when
// the normals differ by more than 90 deg), so that the estimate's own
// covariance weighs it: NEES = e^T C_estimate^-1 e. LineDifference(estimate,
// truth) is expressed in the truth's description instead, and differs in the
// sign of rho where the two descriptions differ: for lines near the origin,
// whose rho-alpha correlation is strong, that makes NEES meaningless.
Eigen::Vector2d LineError(const HesseLine& estimate, const HesseLine& truth);

// A line fitted by weighted total least squares, with its covariance.
struct LineFit {
  HesseLine line;
  // Covariance of (rho_m, alpha_rad), m^2, m rad, rad^2.
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  // Weighted RMS of the orthogonal residuals, sqrt(sum w d^2 / sum w), metres.
  double rms_residual_m = 0.0;
};

// Fits a line to points p_i with weights w_i > 0, minimizing sum w_i d_i^2 of
// orthogonal distances d_i (weighted total least squares: the line passes
// through the weighted centroid c, its direction is the principal axis of the
// weighted scatter). The covariance is the first-order result for isotropic
// point noise of standard deviation sigma_m / sqrt(w_i) (Arras & Siegwart 1997,
// "Feature extraction and scene interpretation for map-based navigation and map
// building", SPIE Mobile Robotics XII; Pfister, Roumeliotis & Burdick 2003,
// ICRA): with s_i the coordinate of p_i along the line from c, W = sum w_i,
// S = sum w_i s_i^2 and s_0 = Direction() . c,
//
//   var(alpha) = sigma^2 / S
//   var(rho)   = sigma^2 / W + s_0^2 sigma^2 / S
//   cov(rho, alpha) = s_0 sigma^2 / S.
//
// weights may be empty (all 1) or have one entry per point. Fails for fewer
// than two points, non-finite input, non-positive weights or sigma_m, and
// when the points do not span a direction (S ~ 0). The covariance is
// first-order: it assumes the points lie along a line (small residuals compared
// with the spread S / W); check rms_residual_m against sigma_m.
core::Result<LineFit> FitLineTls(std::span<const Eigen::Vector2d> points_m,
                                 std::span<const double> weights, double sigma_m);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_HESSE_LINE_H_
