// The SE(2) relative-pose factor: a measured pose of b seen from a, Z = T_a_b,
// from wheel odometry between two keyframes or from a LiDAR scan match.
//
//   E = Z^-1 * T_w_a^-1 * T_w_b,   r = S * Log(E)   (3-vector: x, y, theta)
//
// S is a square root of the information matrix (S^T S = Lambda). It may be
// rank deficient: a scan match in a corridor carries no information along the
// aisle, and SqrtInformation() below keeps only the well-constrained
// directions (rows of zeros elsewhere), so the factor pulls only where the
// sensor actually constrains the pose.
//
// Jacobians with respect to right perturbations of the poses (se2.h):
//   dr/da = -S Jr^-1(Log E) Ad(T_a_b^-1),   dr/db = S Jr^-1(Log E),
// with T_a_b = T_w_a^-1 T_w_b. Ceres stores each pose as an ambient block
// (x, y, yaw) under core::SE2Manifold; Evaluate() returns ambient Jacobians
// J_tangent * [R^T 0; 0 1], which the manifold's Plus Jacobian [R 0; 0 1]
// turns back into J_tangent (the "lift" of OKVIS and Basalt).
//
// Thread-safety: immutable after construction; Evaluate may run concurrently.
#ifndef GROUNDLINE_LOCALIZATION_RELATIVE_POSE_FACTOR_H_
#define GROUNDLINE_LOCALIZATION_RELATIVE_POSE_FACTOR_H_

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::localization {

// A square root S of a symmetric positive semi-definite information matrix,
// S^T S = information, from its eigen-decomposition: directions whose
// eigenvalue is below min_eigenvalue (absolute) carry no information and get
// zero rows. Fails when the matrix is not symmetric, not finite or has an
// eigenvalue below -min_eigenvalue (not PSD).
core::Result<Eigen::Matrix3d> SqrtInformation(const Eigen::Matrix3d& information,
                                              double min_eigenvalue = 1e-12);

// The square root of the inverse of a symmetric positive definite covariance.
core::Result<Eigen::Matrix3d> SqrtInformationFromCovariance(const Eigen::Matrix3d& covariance);

// Ambient (x, y, yaw) Jacobian of a residual from its right-perturbation
// (tangent) Jacobian at a pose with the given yaw: J_tangent * [R^T 0; 0 1].
Eigen::Matrix3d AmbientFromTangentJacobian(const Eigen::Matrix3d& J_tangent, double yaw_rad);
// The same for a residual of any size (rows), e.g. the 2x3 pose Jacobians of
// the floor factors.
Eigen::MatrixX3d AmbientFromTangentJacobianRows(const Eigen::Ref<const Eigen::MatrixX3d>& J_tangent,
                                                double yaw_rad);

class RelativePoseFactor final : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  // T_a_b_measured: the measured pose of b in a; sqrt_information: S above.
  RelativePoseFactor(const core::SE2& T_a_b_measured, const Eigen::Matrix3d& sqrt_information);

  // The whitened residual and its tangent Jacobians (optional outputs).
  core::Vector3 Residual(const core::SE2& T_w_a, const core::SE2& T_w_b,
                         core::Matrix3* J_r_a = nullptr, core::Matrix3* J_r_b = nullptr) const;

  // parameters[0] = T_w_a, parameters[1] = T_w_b, each (x, y, yaw).
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const core::SE2& measurement() const { return T_a_b_measured_; }
  const Eigen::Matrix3d& sqrt_information() const { return sqrt_information_; }

 private:
  core::SE2 T_b_a_measured_;  // Z^-1, precomputed
  core::SE2 T_a_b_measured_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_RELATIVE_POSE_FACTOR_H_
