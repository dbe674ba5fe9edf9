// SE2Manifold: lets Ceres optimize a planar pose stored as three doubles
// (x_m, y_m, yaw_rad), the ambient parameterization of SE2::Vector().
//
//   Plus(x, delta)  = x * Exp(delta)   (right perturbation, yaw wrapped to [-pi, pi])
//   Minus(y, x)     = Log(x^-1 * y)
//
// so the tangent space, its (x, y, theta) order and the meaning of a
// covariance that Ceres returns for the block (ceres::Covariance with
// GetCovarianceBlockInTangentSpace) are those of core::SE2 and
// docs/conventions.md. Jacobians are row-major, as Ceres requires:
//
//   PlusJacobian(x)  = d Plus(x, delta) / d delta at delta = 0  = [R 0; 0 1]   (3x3)
//   MinusJacobian(x) = d Minus(y, x) / d y        at y = x      = [R^T 0; 0 1] (3x3)
//
// The stored yaw is wrapped, so the ambient coordinates jump by 2 pi at
// +-pi. Residuals must therefore depend on yaw only through sin/cos or
// through SE2 (never on the raw number), which all groundline factors do.
//
// Stateless and thread-safe; a Problem may share one instance among blocks
// only if it does not own it (see ceres::Problem::Options::manifold_ownership).
#ifndef GROUNDLINE_CORE_SE2_MANIFOLD_H_
#define GROUNDLINE_CORE_SE2_MANIFOLD_H_

#include <ceres/manifold.h>

#include <array>

#include "groundline/core/se2.h"

namespace groundline::core {

// The pose stored in ambient coordinates (x_m, y_m, yaw_rad), and back.
inline SE2 PoseFromAmbient(const double* x) { return SE2(x[0], x[1], x[2]); }
inline SE2 PoseFromAmbient(const std::array<double, 3>& x) { return PoseFromAmbient(x.data()); }
inline std::array<double, 3> AmbientOf(const SE2& T) { return {T.x(), T.y(), T.yaw()}; }

class SE2Manifold final : public ceres::Manifold {
 public:
  static constexpr int kAmbientSize = 3;
  static constexpr int kTangentSize = 3;

  int AmbientSize() const override { return kAmbientSize; }
  int TangentSize() const override { return kTangentSize; }

  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool RightMultiplyByPlusJacobian(const double* x, int num_rows, const double* ambient_matrix,
                                   double* tangent_matrix) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_SE2_MANIFOLD_H_
