// The special Euclidean group SE(2): planar rigid motions.
//
// Conventions (see docs/conventions.md):
// - An element T_a_b maps points from frame b into frame a: p_a = T_a_b * p_b.
//   Composition chains frames: T_a_c = T_a_b * T_b_c.
// - Tangent vectors are ordered translation first: xi = (rho_x, rho_y, theta),
//   metres and radians, as in manif and Sophus.
// - Perturbations are on the right ("local"): T (+) d = T * Exp(d), and
//   Y (-) X = Log(X^-1 * Y). Every Jacobian below is the derivative with respect
//   to such right perturbations: for f: SE(2) -> SE(2),
//   J = d Log(f(X)^-1 f(X Exp(d))) / dd at d = 0 (Sola, Deray, Atchuthan,
//   "A micro Lie theory for state estimation in robotics", 2018, eq. 41).
// - The angle is stored wrapped to [-pi, pi].
//
// Jacobians are optional output arguments: pass nullptr (the default) to skip
// them. All functions are pure; SE2 is a small value type and thread-safe.
#ifndef GROUNDLINE_CORE_SE2_H_
#define GROUNDLINE_CORE_SE2_H_

#include <Eigen/Core>

namespace groundline::core {

using Vector2 = Eigen::Vector2d;
using Vector3 = Eigen::Vector3d;
using Matrix2 = Eigen::Matrix2d;
using Matrix3 = Eigen::Matrix3d;
using Matrix23 = Eigen::Matrix<double, 2, 3>;

// Wraps an angle to [-pi, pi].
double WrapAngle(double angle_rad);

class SE2 {
 public:
  // The identity.
  SE2() = default;
  SE2(double x_m, double y_m, double yaw_rad);
  SE2(const Vector2& translation_m, double yaw_rad);

  static SE2 Identity() { return SE2(); }

  // Exp: R^3 -> SE(2). J_T_xi is the right Jacobian Jr(xi).
  static SE2 Exp(const Vector3& xi, Matrix3* J_T_xi = nullptr);
  // Log: SE(2) -> R^3, theta in [-pi, pi]. J_xi_T is Jr^-1(Log(T)).
  Vector3 Log(Matrix3* J_xi_T = nullptr) const;

  // this * other. J_out_this = Ad(other^-1), J_out_other = I.
  SE2 Compose(const SE2& other, Matrix3* J_out_this = nullptr,
              Matrix3* J_out_other = nullptr) const;
  SE2 operator*(const SE2& other) const { return Compose(other); }

  // this^-1. J_out_this = -Ad(this).
  SE2 Inverse(Matrix3* J_out_this = nullptr) const;

  // this^-1 * other, the pose of `other` seen from `this`.
  // J_out_this = -Ad(out^-1), J_out_other = I.
  SE2 Between(const SE2& other, Matrix3* J_out_this = nullptr,
              Matrix3* J_out_other = nullptr) const;

  // Transforms a point: p_a = T_a_b * p_b.
  // J_out_this = [R, R * (-p.y, p.x)^T] (2x3), J_out_point = R.
  Vector2 Act(const Vector2& point, Matrix23* J_out_this = nullptr,
              Matrix2* J_out_point = nullptr) const;
  Vector2 operator*(const Vector2& point) const { return Act(point); }

  // Right plus / minus on the manifold.
  // Plus: this * Exp(delta); J_out_this = Ad(Exp(delta)^-1), J_out_delta = Jr(delta).
  SE2 Plus(const Vector3& delta, Matrix3* J_out_this = nullptr,
           Matrix3* J_out_delta = nullptr) const;
  // Minus: Log(other^-1 * this) ("this (-) other").
  // J_out_this = Jr^-1(out), J_out_other = -Jl^-1(out).
  Vector3 Minus(const SE2& other, Matrix3* J_out_this = nullptr,
                Matrix3* J_out_other = nullptr) const;

  // Adjoint matrix: Ad(T) * xi = Log(T Exp(xi) T^-1) to first order.
  // [R, (y, -x)^T; 0 0 1].
  Matrix3 Adjoint() const;

  // Right and left Jacobians of SE(2) and their inverses.
  static Matrix3 RightJacobian(const Vector3& xi);
  static Matrix3 LeftJacobian(const Vector3& xi);
  static Matrix3 RightJacobianInverse(const Vector3& xi);
  static Matrix3 LeftJacobianInverse(const Vector3& xi);

  // The 3x3 homogeneous matrix [R t; 0 0 1].
  Matrix3 Matrix() const;
  Matrix2 Rotation() const;

  const Vector2& translation() const { return translation_m_; }
  double x() const { return translation_m_.x(); }
  double y() const { return translation_m_.y(); }
  double yaw() const { return yaw_rad_; }
  // (x, y, yaw): the ambient parameterization used by the Ceres manifold.
  Vector3 Vector() const { return {translation_m_.x(), translation_m_.y(), yaw_rad_}; }

  // True if translations agree within tol_m and angles within tol_rad (wrapped).
  bool IsApprox(const SE2& other, double tol_m = 1e-9, double tol_rad = 1e-9) const;

 private:
  Vector2 translation_m_ = Vector2::Zero();
  double yaw_rad_ = 0.0;
};

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_SE2_H_
