#include "groundline/localization/floor_factors.h"

#include <Eigen/Cholesky>

#include "groundline/core/se2_manifold.h"
#include "groundline/localization/relative_pose_factor.h"

namespace groundline::localization {
namespace {

using RowMajor23 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
using RowMajor22 = Eigen::Matrix<double, 2, 2, Eigen::RowMajor>;
using RowMajor33 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

}  // namespace

core::Result<Eigen::Matrix2d> SqrtInformationFromCovariance2(const Eigen::Matrix2d& covariance) {
  if (!covariance.allFinite()) return core::Status::Error("covariance has a non-finite entry");
  const Eigen::LLT<Eigen::Matrix2d> llt(covariance);
  if (llt.info() != Eigen::Success) {
    return core::Status::Error("covariance is not positive definite");
  }
  const Eigen::Matrix2d L = llt.matrixL();
  return Eigen::Matrix2d(L.triangularView<Eigen::Lower>().solve(Eigen::Matrix2d::Identity()));
}

GroundLineFactor::GroundLineFactor(const perception::HesseLine& measured_base,
                                   const Eigen::Matrix2d& sqrt_information)
    : measured_base_(measured_base), sqrt_information_(sqrt_information) {}

Eigen::Vector2d GroundLineFactor::Residual(const core::SE2& T_map_base,
                                           const perception::HesseLine& line_map,
                                           Eigen::Matrix<double, 2, 3>* J_r_T,
                                           Eigen::Matrix2d* J_r_line) const {
  const bool want = J_r_T != nullptr || J_r_line != nullptr;
  perception::Matrix23 J_pred_T;
  Eigen::Matrix2d J_pred_line;
  const perception::HesseLine predicted = perception::InverseTransformLine(
      T_map_base, line_map, want ? &J_pred_T : nullptr, want ? &J_pred_line : nullptr);
  Eigen::Matrix2d J_d_pred;
  const Eigen::Vector2d difference =
      perception::LineDifference(predicted, measured_base_, want ? &J_d_pred : nullptr);
  if (J_r_T != nullptr) *J_r_T = sqrt_information_ * J_d_pred * J_pred_T;
  if (J_r_line != nullptr) *J_r_line = sqrt_information_ * J_d_pred * J_pred_line;
  return sqrt_information_ * difference;
}

bool GroundLineFactor::Evaluate(double const* const* parameters, double* residuals,
                                double** jacobians) const {
  const core::SE2 T_map_base = core::PoseFromAmbient(parameters[0]);
  const perception::HesseLine line_map{parameters[1][0], parameters[1][1]};
  const bool want_T = jacobians != nullptr && jacobians[0] != nullptr;
  const bool want_line = jacobians != nullptr && jacobians[1] != nullptr;
  Eigen::Matrix<double, 2, 3> J_T;
  Eigen::Matrix2d J_line;
  Eigen::Map<Eigen::Vector2d>{residuals} =
      Residual(T_map_base, line_map, want_T ? &J_T : nullptr, want_line ? &J_line : nullptr);
  if (want_T) {
    Eigen::Map<RowMajor23>{jacobians[0]} = AmbientFromTangentJacobianRows(J_T, parameters[0][2]);
  }
  if (want_line) Eigen::Map<RowMajor22>{jacobians[1]} = J_line;
  return true;
}

JunctionFactor::JunctionFactor(const Eigen::Vector2d& measured_base_m,
                               const Eigen::Matrix2d& sqrt_information)
    : measured_base_m_(measured_base_m), sqrt_information_(sqrt_information) {}

Eigen::Vector2d JunctionFactor::Residual(const core::SE2& T_map_base,
                                         const Eigen::Vector2d& point_map_m,
                                         Eigen::Matrix<double, 2, 3>* J_r_T,
                                         Eigen::Matrix2d* J_r_point) const {
  const Eigen::Matrix2d R_T = T_map_base.Rotation().transpose();
  const Eigen::Vector2d p_base = R_T * (point_map_m - T_map_base.translation());
  // Exp(d)^-1 p ~ p - d_t - d_theta (-p_y, p_x).
  if (J_r_T != nullptr) {
    Eigen::Matrix<double, 2, 3> J;
    J << -1.0, 0.0, p_base.y(), 0.0, -1.0, -p_base.x();
    *J_r_T = sqrt_information_ * J;
  }
  if (J_r_point != nullptr) *J_r_point = sqrt_information_ * R_T;
  return sqrt_information_ * (p_base - measured_base_m_);
}

bool JunctionFactor::Evaluate(double const* const* parameters, double* residuals,
                              double** jacobians) const {
  const core::SE2 T_map_base = core::PoseFromAmbient(parameters[0]);
  const Eigen::Vector2d point(parameters[1][0], parameters[1][1]);
  const bool want_T = jacobians != nullptr && jacobians[0] != nullptr;
  const bool want_point = jacobians != nullptr && jacobians[1] != nullptr;
  Eigen::Matrix<double, 2, 3> J_T;
  Eigen::Matrix2d J_point;
  Eigen::Map<Eigen::Vector2d>{residuals} =
      Residual(T_map_base, point, want_T ? &J_T : nullptr, want_point ? &J_point : nullptr);
  if (want_T) {
    Eigen::Map<RowMajor23>{jacobians[0]} = AmbientFromTangentJacobianRows(J_T, parameters[0][2]);
  }
  if (want_point) Eigen::Map<RowMajor22>{jacobians[1]} = J_point;
  return true;
}

PosePriorFactor::PosePriorFactor(const core::SE2& T_prior, const Eigen::Matrix3d& sqrt_information)
    : T_prior_(T_prior), sqrt_information_(sqrt_information) {}

core::Vector3 PosePriorFactor::Residual(const core::SE2& T, core::Matrix3* J_r_T) const {
  core::Matrix3 J_e_T;
  const core::Vector3 e = T.Minus(T_prior_, J_r_T != nullptr ? &J_e_T : nullptr);
  if (J_r_T != nullptr) *J_r_T = sqrt_information_ * J_e_T;
  return sqrt_information_ * e;
}

bool PosePriorFactor::Evaluate(double const* const* parameters, double* residuals,
                               double** jacobians) const {
  const bool want = jacobians != nullptr && jacobians[0] != nullptr;
  core::Matrix3 J;
  Eigen::Map<Eigen::Vector3d>{residuals} =
      Residual(core::PoseFromAmbient(parameters[0]), want ? &J : nullptr);
  if (want) Eigen::Map<RowMajor33>{jacobians[0]} = AmbientFromTangentJacobian(J, parameters[0][2]);
  return true;
}

}  // namespace groundline::localization
