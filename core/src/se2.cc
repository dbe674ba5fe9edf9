#include "groundline/core/se2.h"

#include <cmath>
#include <numbers>

#include <Eigen/LU>

namespace groundline::core {
namespace {

// Below this |theta| the closed forms lose precision to cancellation; the
// Taylor series are used instead (their truncation error is below 1e-17).
constexpr double kSmallAngleRad = 1e-4;

// sin(t)/t
double SinOverT(double t) {
  if (std::abs(t) < kSmallAngleRad) return 1.0 - t * t / 6.0;
  return std::sin(t) / t;
}
// 1 - cos(t) written as 2 sin^2(t/2): no cancellation for small t, so the
// values stay smooth across the series switch.
double OneMinusCos(double t) {
  const double s = std::sin(0.5 * t);
  return 2.0 * s * s;
}
// (1 - cos(t))/t
double OneMinusCosOverT(double t) {
  if (std::abs(t) < kSmallAngleRad) return t / 2.0 - t * t * t / 24.0;
  return OneMinusCos(t) / t;
}
// (t - sin(t))/t^2
double TMinusSinOverT2(double t) {
  if (std::abs(t) < kSmallAngleRad) return t / 6.0 - t * t * t / 120.0;
  return (t - std::sin(t)) / (t * t);
}
// (1 - cos(t))/t^2
double OneMinusCosOverT2(double t) {
  if (std::abs(t) < kSmallAngleRad) return 0.5 - t * t / 24.0;
  return OneMinusCos(t) / (t * t);
}

Matrix2 RotationMatrix(double yaw_rad) {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  Matrix2 r;
  r << c, -s, s, c;
  return r;
}

}  // namespace

double WrapAngle(double angle_rad) {
  // std::remainder rounds the quotient to nearest, so the result is in [-pi, pi].
  return std::remainder(angle_rad, 2.0 * std::numbers::pi);
}

SE2::SE2(double x_m, double y_m, double yaw_rad)
    : translation_m_(x_m, y_m), yaw_rad_(WrapAngle(yaw_rad)) {}

SE2::SE2(const Vector2& translation_m, double yaw_rad)
    : translation_m_(translation_m), yaw_rad_(WrapAngle(yaw_rad)) {}

SE2 SE2::Exp(const Vector3& xi, Matrix3* J_T_xi) {
  const double theta = xi.z();
  const double a = SinOverT(theta);
  const double b = OneMinusCosOverT(theta);
  // t = V(theta) * rho with V = [a, -b; b, a].
  const Vector2 t(a * xi.x() - b * xi.y(), b * xi.x() + a * xi.y());
  if (J_T_xi != nullptr) *J_T_xi = RightJacobian(xi);
  return SE2(t, theta);
}

Vector3 SE2::Log(Matrix3* J_xi_T) const {
  const double theta = yaw_rad_;
  const double a = SinOverT(theta);
  const double b = OneMinusCosOverT(theta);
  // rho = V^-1 t, V^-1 = [a, b; -b, a] / (a^2 + b^2).
  const double inv_det = 1.0 / (a * a + b * b);
  const Vector2& t = translation_m_;
  Vector3 xi(inv_det * (a * t.x() + b * t.y()), inv_det * (-b * t.x() + a * t.y()), theta);
  if (J_xi_T != nullptr) *J_xi_T = RightJacobianInverse(xi);
  return xi;
}

SE2 SE2::Compose(const SE2& other, Matrix3* J_out_this, Matrix3* J_out_other) const {
  if (J_out_this != nullptr) *J_out_this = other.Inverse().Adjoint();
  if (J_out_other != nullptr) J_out_other->setIdentity();
  return SE2(translation_m_ + Rotation() * other.translation_m_, yaw_rad_ + other.yaw_rad_);
}

SE2 SE2::Inverse(Matrix3* J_out_this) const {
  if (J_out_this != nullptr) *J_out_this = -Adjoint();
  return SE2(-(Rotation().transpose() * translation_m_), -yaw_rad_);
}

SE2 SE2::Between(const SE2& other, Matrix3* J_out_this, Matrix3* J_out_other) const {
  const SE2 out = Inverse().Compose(other);
  if (J_out_this != nullptr) *J_out_this = -out.Inverse().Adjoint();
  if (J_out_other != nullptr) J_out_other->setIdentity();
  return out;
}

Vector2 SE2::Act(const Vector2& point, Matrix23* J_out_this, Matrix2* J_out_point) const {
  const Matrix2 r = Rotation();
  if (J_out_this != nullptr) {
    J_out_this->leftCols<2>() = r;
    J_out_this->col(2) = r * Vector2(-point.y(), point.x());
  }
  if (J_out_point != nullptr) *J_out_point = r;
  return r * point + translation_m_;
}

SE2 SE2::Plus(const Vector3& delta, Matrix3* J_out_this, Matrix3* J_out_delta) const {
  const SE2 step = Exp(delta, J_out_delta);
  return Compose(step, J_out_this);
}

Vector3 SE2::Minus(const SE2& other, Matrix3* J_out_this, Matrix3* J_out_other) const {
  const Vector3 out = other.Between(*this).Log();
  if (J_out_this != nullptr) *J_out_this = RightJacobianInverse(out);
  if (J_out_other != nullptr) *J_out_other = -LeftJacobianInverse(out);
  return out;
}

Matrix3 SE2::Adjoint() const {
  Matrix3 ad = Matrix3::Identity();
  ad.topLeftCorner<2, 2>() = Rotation();
  ad(0, 2) = translation_m_.y();
  ad(1, 2) = -translation_m_.x();
  return ad;
}

Matrix3 SE2::RightJacobian(const Vector3& xi) {
  const double theta = xi.z();
  const double a = SinOverT(theta);
  const double b = OneMinusCosOverT(theta);
  const double c = TMinusSinOverT2(theta);
  const double d = OneMinusCosOverT2(theta);
  Matrix3 j;
  j << a, b, xi.x() * c - xi.y() * d,  //
      -b, a, xi.x() * d + xi.y() * c,  //
      0.0, 0.0, 1.0;
  return j;
}

Matrix3 SE2::LeftJacobian(const Vector3& xi) {
  const double theta = xi.z();
  const double a = SinOverT(theta);
  const double b = OneMinusCosOverT(theta);
  const double c = TMinusSinOverT2(theta);
  const double d = OneMinusCosOverT2(theta);
  Matrix3 j;
  j << a, -b, xi.x() * c + xi.y() * d,  //
      b, a, -xi.x() * d + xi.y() * c,   //
      0.0, 0.0, 1.0;
  return j;
}

Matrix3 SE2::RightJacobianInverse(const Vector3& xi) {
  // J = [M, m; 0, 1] with M = [a, b; -b, a]  =>  J^-1 = [M^-1, -M^-1 m; 0, 1].
  const Matrix3 j = RightJacobian(xi);
  const Matrix2 m_inv = j.topLeftCorner<2, 2>().inverse();
  Matrix3 inv = Matrix3::Identity();
  inv.topLeftCorner<2, 2>() = m_inv;
  inv.topRightCorner<2, 1>() = -m_inv * j.topRightCorner<2, 1>();
  return inv;
}

Matrix3 SE2::LeftJacobianInverse(const Vector3& xi) {
  const Matrix3 j = LeftJacobian(xi);
  const Matrix2 m_inv = j.topLeftCorner<2, 2>().inverse();
  Matrix3 inv = Matrix3::Identity();
  inv.topLeftCorner<2, 2>() = m_inv;
  inv.topRightCorner<2, 1>() = -m_inv * j.topRightCorner<2, 1>();
  return inv;
}

Matrix3 SE2::Matrix() const {
  Matrix3 m = Matrix3::Identity();
  m.topLeftCorner<2, 2>() = Rotation();
  m.topRightCorner<2, 1>() = translation_m_;
  return m;
}

Matrix2 SE2::Rotation() const { return RotationMatrix(yaw_rad_); }

bool SE2::IsApprox(const SE2& other, double tol_m, double tol_rad) const {
  return (translation_m_ - other.translation_m_).norm() <= tol_m &&
         std::abs(WrapAngle(yaw_rad_ - other.yaw_rad_)) <= tol_rad;
}

}  // namespace groundline::core
