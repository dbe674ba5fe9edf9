// Factors of the floor markings: a map (atlas) ground line seen as a line in
// base_link, and a map junction seen as a point in base_link. Both are
// ceres::SizedCostFunction with analytic Jacobians; the smoother attaches a
// pseudo-Huber loss (ceres::SoftLOneLoss) to them.
//
// Ground-line factor (Hesse normal line residual, seed paper eqs. 51-53):
//   l_pred = InverseTransformLine(T_map_base, l_map)     map line in base_link
//   r      = S * LineDifference(l_pred, z)               (rho_m, wrapped alpha_rad)
// with S^T S = Sigma_z^-1 (Sigma_z: the measurement's 2x2 covariance).
//
// Parameterization of the map line. The line is its own parameter block of
// two doubles (rho_m, alpha_rad), Euclidean (no manifold), which may hold
// either signed description of the line: rho of any sign, alpha unwrapped.
// The residual depends on the block only through the line it describes
// (InverseTransformLine normalizes, LineDifference compares the descriptions
// whose normals differ by at most 90 deg), so it is invariant to
// (rho, alpha) -> (-rho, alpha + pi) and alpha -> alpha + 2 pi and is
// continuous when the optimizer moves rho through 0: there is no sign
// discontinuity for the solver to trip over. Normalize the block
// (perception::NormalizeLine) when reading it back. The residual jumps only
// where predicted and measured normals are perpendicular, far outside any
// association gate.
//
// Junction factor:  r = S * (T_map_base^-1 * p_map - z),  S^T S = Sigma_z^-1.
//
// Jacobians are with respect to right perturbations of the pose (core::SE2)
// and the Euclidean coordinates of the landmark. Evaluate() lifts the pose
// Jacobian to the ambient (x, y, yaw) block of core::SE2Manifold
// (AmbientFromTangentJacobianRows, relative_pose_factor.h).
//
// Thread-safety: immutable after construction; Evaluate may run concurrently.
#ifndef GROUNDLINE_LOCALIZATION_FLOOR_FACTORS_H_
#define GROUNDLINE_LOCALIZATION_FLOOR_FACTORS_H_

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::localization {

// S with S^T S = covariance^-1 (S = L^-1 for covariance = L L^T). Fails when
// the covariance is not finite or not positive definite.
core::Result<Eigen::Matrix2d> SqrtInformationFromCovariance2(const Eigen::Matrix2d& covariance);

class GroundLineFactor final : public ceres::SizedCostFunction<2, 3, 2> {
 public:
  // measured_base: the observed line in base_link; sqrt_information: S above.
  GroundLineFactor(const perception::HesseLine& measured_base,
                   const Eigen::Matrix2d& sqrt_information);

  // J_r_T: 2x3 (right perturbation of T_map_base), J_r_line: 2x2 (rho, alpha of line_map).
  Eigen::Vector2d Residual(const core::SE2& T_map_base, const perception::HesseLine& line_map,
                           Eigen::Matrix<double, 2, 3>* J_r_T = nullptr,
                           Eigen::Matrix2d* J_r_line = nullptr) const;

  // parameters[0] = T_map_base (x, y, yaw), parameters[1] = line_map (rho, alpha).
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // A new weight (the landmark's shared error spread over more sightings).
  void set_sqrt_information(const Eigen::Matrix2d& sqrt_information) {
    sqrt_information_ = sqrt_information;
  }

 private:
  perception::HesseLine measured_base_;
  Eigen::Matrix2d sqrt_information_;
};

class JunctionFactor final : public ceres::SizedCostFunction<2, 3, 2> {
 public:
  JunctionFactor(const Eigen::Vector2d& measured_base_m, const Eigen::Matrix2d& sqrt_information);

  // J_r_T: 2x3 (right perturbation of T_map_base), J_r_point: 2x2.
  Eigen::Vector2d Residual(const core::SE2& T_map_base, const Eigen::Vector2d& point_map_m,
                           Eigen::Matrix<double, 2, 3>* J_r_T = nullptr,
                           Eigen::Matrix2d* J_r_point = nullptr) const;

  // parameters[0] = T_map_base (x, y, yaw), parameters[1] = point_map (x_m, y_m).
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  void set_sqrt_information(const Eigen::Matrix2d& sqrt_information) {
    sqrt_information_ = sqrt_information;
  }

 private:
  Eigen::Vector2d measured_base_m_;
  Eigen::Matrix2d sqrt_information_;
};

// A prior on one pose:  r = S * Log(Z^-1 * T),  dr/dT = S Jr^-1(Log(Z^-1 T)).
class PosePriorFactor final : public ceres::SizedCostFunction<3, 3> {
 public:
  PosePriorFactor(const core::SE2& T_prior, const Eigen::Matrix3d& sqrt_information);

  core::Vector3 Residual(const core::SE2& T, core::Matrix3* J_r_T = nullptr) const;

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  core::SE2 T_prior_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_FLOOR_FACTORS_H_
