#include "groundline/perception/hesse_line.h"

#include <cmath>
#include <numbers>
#include <sstream>

namespace groundline::perception {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMinPointSeparationM = 1e-9;

// Wraps to (-pi, pi].
double WrapHalfOpen(double angle_rad) {
  const double wrapped = core::WrapAngle(angle_rad);
  return wrapped <= -kPi ? kPi : wrapped;
}

// NormalizeLine that also reports whether the description was flipped to
// (-rho, alpha + pi): *rho_sign is -1 then, else +1. Jacobian rows of rho are
// multiplied by it.
HesseLine NormalizeWithSign(double rho_m, double alpha_rad, double* rho_sign) {
  *rho_sign = 1.0;
  if (rho_m < 0.0) {
    rho_m = -rho_m;
    alpha_rad += kPi;
    *rho_sign = -1.0;
  }
  alpha_rad = WrapHalfOpen(alpha_rad);
  if (rho_m == 0.0) {
    rho_m = 0.0;  // drops a negative zero
    if (alpha_rad > kPi / 2) {
      alpha_rad -= kPi;
      *rho_sign = -*rho_sign;
    } else if (alpha_rad <= -kPi / 2) {
      alpha_rad += kPi;
      *rho_sign = -*rho_sign;
    }
  }
  return HesseLine{rho_m, alpha_rad};
}

Eigen::Vector2d UnitVector(double angle_rad) { return {std::cos(angle_rad), std::sin(angle_rad)}; }

}  // namespace

Eigen::Vector2d HesseLine::Normal() const { return UnitVector(alpha_rad); }

Eigen::Vector2d HesseLine::Direction() const { return {-std::sin(alpha_rad), std::cos(alpha_rad)}; }

HesseLine NormalizeLine(double rho_m, double alpha_rad) {
  double sign = 1.0;
  return NormalizeWithSign(rho_m, alpha_rad, &sign);
}

HesseLine NormalizeLine(double rho_m, double alpha_rad, Eigen::Matrix2d* covariance) {
  double sign = 1.0;
  const HesseLine line = NormalizeWithSign(rho_m, alpha_rad, &sign);
  if (covariance != nullptr && sign < 0.0) {
    (*covariance)(0, 1) = -(*covariance)(0, 1);
    (*covariance)(1, 0) = -(*covariance)(1, 0);
  }
  return line;
}

bool IsNormalized(const HesseLine& line) {
  if (!(line.rho_m >= 0.0 && line.alpha_rad > -kPi && line.alpha_rad <= kPi)) return false;
  return line.rho_m != 0.0 || (line.alpha_rad > -kPi / 2 && line.alpha_rad <= kPi / 2);
}

core::Result<HesseLine> LineFromPoints(const Eigen::Vector2d& p1_m, const Eigen::Vector2d& p2_m,
                                       Eigen::Matrix2d* J_line_p1, Eigen::Matrix2d* J_line_p2) {
  const Eigen::Vector2d d = p2_m - p1_m;
  const double length2 = d.squaredNorm();
  if (!(std::sqrt(length2) >= kMinPointSeparationM)) {
    std::ostringstream out;
    out << "LineFromPoints: the points (" << p1_m.x() << ", " << p1_m.y() << ") and (" << p2_m.x()
        << ", " << p2_m.y() << ") m coincide or are not finite; a line needs two distinct points";
    return core::Status::Error(out.str());
  }
  // Normal (d.y, -d.x) / |d|, i.e. alpha = atan2(-d.x, d.y) (seed paper eq. 45).
  const double alpha_rad = std::atan2(-d.x(), d.y());
  double sign = 1.0;
  const HesseLine line = NormalizeWithSign(UnitVector(alpha_rad).dot(p1_m), alpha_rad, &sign);
  // d alpha / d p2 = (-d.y, d.x) / |d|^2 = -d alpha / d p1 (either description).
  const Eigen::RowVector2d J_alpha_p2 = Eigen::RowVector2d(-d.y(), d.x()) / length2;
  // rho = n(alpha) . p1 holds for the normalized description too.
  const double tangential_p1 = line.Direction().dot(p1_m);
  if (J_line_p1 != nullptr) {
    J_line_p1->row(0) = line.Normal().transpose() - tangential_p1 * J_alpha_p2;
    J_line_p1->row(1) = -J_alpha_p2;
  }
  if (J_line_p2 != nullptr) {
    J_line_p2->row(0) = tangential_p1 * J_alpha_p2;
    J_line_p2->row(1) = J_alpha_p2;
  }
  return line;
}

double SignedDistance(const HesseLine& line, const Eigen::Vector2d& point_m,
                      Eigen::RowVector2d* J_d_line, Eigen::RowVector2d* J_d_point) {
  const Eigen::Vector2d n = line.Normal();
  if (J_d_line != nullptr) *J_d_line << -1.0, line.Direction().dot(point_m);
  if (J_d_point != nullptr) *J_d_point = n.transpose();
  return n.dot(point_m) - line.rho_m;
}

HesseLine TransformLine(const core::SE2& T_a_b, const HesseLine& line_b, Matrix23* J_la_T,
                        Eigen::Matrix2d* J_la_lb) {
  const double alpha_a = line_b.alpha_rad + T_a_b.yaw();
  const Eigen::Vector2d n_a = UnitVector(alpha_a);
  const Eigen::Vector2d dir_a(-n_a.y(), n_a.x());
  const Eigen::Vector2d& t = T_a_b.translation();
  double sign = 1.0;
  const HesseLine line_a = NormalizeWithSign(line_b.rho_m + n_a.dot(t), alpha_a, &sign);
  // Right perturbation: t -> t + R dt, theta -> theta + dtheta (first order).
  if (J_la_T != nullptr) {
    J_la_T->row(0) << sign * (n_a.transpose() * T_a_b.Rotation()), sign * dir_a.dot(t);
    J_la_T->row(1) << 0.0, 0.0, 1.0;
  }
  if (J_la_lb != nullptr) *J_la_lb << sign, sign * dir_a.dot(t), 0.0, 1.0;
  return line_a;
}

HesseLine InverseTransformLine(const core::SE2& T_a_b, const HesseLine& line_a, Matrix23* J_lb_T,
                               Eigen::Matrix2d* J_lb_la) {
  const Eigen::Vector2d n_a = line_a.Normal();
  const Eigen::Vector2d& t = T_a_b.translation();
  double sign = 1.0;
  const HesseLine line_b =
      NormalizeWithSign(line_a.rho_m - n_a.dot(t), line_a.alpha_rad - T_a_b.yaw(), &sign);
  if (J_lb_T != nullptr) {
    J_lb_T->row(0) << -sign * (n_a.transpose() * T_a_b.Rotation()), 0.0;
    J_lb_T->row(1) << 0.0, 0.0, -1.0;
  }
  if (J_lb_la != nullptr) *J_lb_la << sign, -sign * line_a.Direction().dot(t), 0.0, 1.0;
  return line_b;
}

Eigen::Vector2d LineDifference(const HesseLine& a, const HesseLine& b, Eigen::Matrix2d* J_r_a,
                               Eigen::Matrix2d* J_r_b) {
  double delta_alpha = core::WrapAngle(a.alpha_rad - b.alpha_rad);
  double rho_a = a.rho_m;
  double rho_sign = 1.0;
  if (std::abs(delta_alpha) > kPi / 2) {
    // Use a's other description (-rho_a, alpha_a + pi).
    rho_a = -rho_a;
    rho_sign = -1.0;
    delta_alpha = core::WrapAngle(delta_alpha + kPi);
  }
  if (J_r_a != nullptr) *J_r_a << rho_sign, 0.0, 0.0, 1.0;
  if (J_r_b != nullptr) *J_r_b = -Eigen::Matrix2d::Identity();
  return {rho_a - b.rho_m, delta_alpha};
}

Eigen::Matrix2d CovarianceInDescriptionOf(const HesseLine& a, const HesseLine& b,
                                          const Eigen::Matrix2d& covariance_a) {
  Eigen::Matrix2d J;
  LineDifference(a, b, &J);
  return J * covariance_a * J.transpose();
}

Eigen::Vector2d LineError(const HesseLine& estimate, const HesseLine& truth) {
  Eigen::Matrix2d J;
  const Eigen::Vector2d r = LineDifference(estimate, truth, &J);
  return J * r;  // J = diag(+-1, 1) is its own inverse
}

}  // namespace groundline::perception
