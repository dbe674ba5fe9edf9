#include "groundline/localization/relative_pose_factor.h"
#include "groundline/core/se2_manifold.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace groundline::localization {
namespace {

using RowMajorMatrix3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

}  // namespace

core::Result<Eigen::Matrix3d> SqrtInformation(const Eigen::Matrix3d& information,
                                              double min_eigenvalue) {
  if (!information.allFinite()) {
    return core::Status::Error("information matrix has a non-finite entry");
  }
  const double scale = std::max(1.0, information.cwiseAbs().maxCoeff());
  if ((information - information.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    return core::Status::Error("information matrix is not symmetric");
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(information);
  const Eigen::Vector3d& values = eigen.eigenvalues();
  if (values.minCoeff() < -min_eigenvalue) {
    std::ostringstream message;
    message << "information matrix is not positive semi-definite (eigenvalue " << values.minCoeff()
            << ")";
    return core::Status::Error(message.str());
  }
  Eigen::Matrix3d sqrt_information = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (values(i) > min_eigenvalue) {
      sqrt_information.row(i) = std::sqrt(values(i)) * eigen.eigenvectors().col(i).transpose();
    }
  }
  return sqrt_information;
}

core::Result<Eigen::Matrix3d> SqrtInformationFromCovariance(const Eigen::Matrix3d& covariance) {
  if (!covariance.allFinite()) {
    return core::Status::Error("covariance has a non-finite entry");
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
  if (llt.info() != Eigen::Success) {
    return core::Status::Error("covariance is not positive definite");
  }
  // covariance = L L^T  =>  information = L^-T L^-1, so S = L^-1.
  const Eigen::Matrix3d L = llt.matrixL();
  return Eigen::Matrix3d(L.triangularView<Eigen::Lower>().solve(Eigen::Matrix3d::Identity()));
}

Eigen::Matrix3d AmbientFromTangentJacobian(const Eigen::Matrix3d& J_tangent, double yaw_rad) {
  return AmbientFromTangentJacobianRows(J_tangent, yaw_rad);
}

Eigen::MatrixX3d AmbientFromTangentJacobianRows(const Eigen::Ref<const Eigen::MatrixX3d>& J_tangent,
                                                double yaw_rad) {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  Eigen::Matrix3d lift = Eigen::Matrix3d::Identity();
  lift.topLeftCorner<2, 2>() << c, s, -s, c;  // R^T
  return J_tangent * lift;
}

RelativePoseFactor::RelativePoseFactor(const core::SE2& T_a_b_measured,
                                       const Eigen::Matrix3d& sqrt_information)
    : T_b_a_measured_(T_a_b_measured.Inverse()),
      T_a_b_measured_(T_a_b_measured),
      sqrt_information_(sqrt_information) {}

core::Vector3 RelativePoseFactor::Residual(const core::SE2& T_w_a, const core::SE2& T_w_b,
                                           core::Matrix3* J_r_a, core::Matrix3* J_r_b) const {
  const bool want_jacobians = J_r_a != nullptr || J_r_b != nullptr;
  core::Matrix3 J_ab_a;
  const core::SE2 T_a_b = T_w_a.Between(T_w_b, want_jacobians ? &J_ab_a : nullptr);
  // E = Z^-1 * T_a_b: d E / d T_a_b = I (right perturbation of the right factor).
  const core::SE2 error = T_b_a_measured_.Compose(T_a_b);
  core::Matrix3 J_e_E;
  const core::Vector3 e = error.Log(want_jacobians ? &J_e_E : nullptr);
  if (J_r_a != nullptr) *J_r_a = sqrt_information_ * J_e_E * J_ab_a;
  if (J_r_b != nullptr) *J_r_b = sqrt_information_ * J_e_E;
  return sqrt_information_ * e;
}

bool RelativePoseFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const core::SE2 T_w_a = core::PoseFromAmbient(parameters[0]);
  const core::SE2 T_w_b = core::PoseFromAmbient(parameters[1]);
  const bool want_a = jacobians != nullptr && jacobians[0] != nullptr;
  const bool want_b = jacobians != nullptr && jacobians[1] != nullptr;
  core::Matrix3 J_r_a;
  core::Matrix3 J_r_b;
  const core::Vector3 r =
      Residual(T_w_a, T_w_b, want_a ? &J_r_a : nullptr, want_b ? &J_r_b : nullptr);
  Eigen::Map<Eigen::Vector3d> residual_out(residuals);
  residual_out = r;
  if (want_a) {
    Eigen::Map<RowMajorMatrix3> J_out(jacobians[0]);
    J_out = AmbientFromTangentJacobian(J_r_a, parameters[0][2]);
  }
  if (want_b) {
    Eigen::Map<RowMajorMatrix3> J_out(jacobians[1]);
    J_out = AmbientFromTangentJacobian(J_r_b, parameters[1][2]);
  }
  return true;
}

}  // namespace groundline::localization
