#include "groundline/localization/marginalization.h"

#include <Eigen/Eigenvalues>
#include <cassert>
#include <cmath>
#include <sstream>

#include "groundline/core/se2.h"
#include "groundline/localization/relative_pose_factor.h"

namespace groundline::localization {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd Select(const Eigen::MatrixXd& H, std::span<const int> rows,
                       std::span<const int> cols) {
  Eigen::MatrixXd out(rows.size(), cols.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    for (size_t j = 0; j < cols.size(); ++j) out(i, j) = H(rows[i], cols[j]);
  }
  return out;
}

Eigen::VectorXd Select(const Eigen::VectorXd& b, std::span<const int> rows) {
  Eigen::VectorXd out(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) out(i) = b(rows[i]);
  return out;
}

// Tangent Jacobian of an ambient pose Jacobian: J_ambient * [R 0; 0 1].
Eigen::MatrixXd TangentFromAmbientPose(const Eigen::MatrixXd& J_ambient, double yaw_rad) {
  Eigen::Matrix3d plus = Eigen::Matrix3d::Identity();
  plus.topLeftCorner<2, 2>() = core::SE2(0.0, 0.0, yaw_rad).Rotation();
  return J_ambient * plus;
}

}  // namespace

core::Result<LinearSystem> MarginalizeSchur(const LinearSystem& system, std::span<const int> keep,
                                            std::span<const int> marginalize,
                                            double min_eigenvalue) {
  assert(system.H.rows() == system.H.cols() && system.H.rows() == system.b.size());
  if (!system.H.allFinite() || !system.b.allFinite()) {
    return core::Status::Error("marginalization: the linear system has a non-finite entry");
  }
  const Eigen::MatrixXd H_kk = Select(system.H, keep, keep);
  if (marginalize.empty()) return LinearSystem{H_kk, Select(system.b, keep)};
  const Eigen::MatrixXd H_km = Select(system.H, keep, marginalize);
  Eigen::MatrixXd H_mm = Select(system.H, marginalize, marginalize);
  H_mm = 0.5 * (H_mm + H_mm.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(H_mm);
  const Eigen::VectorXd values = eigen.eigenvalues();
  Eigen::VectorXd inverse_values = Eigen::VectorXd::Zero(values.size());
  for (int i = 0; i < values.size(); ++i) {
    if (values(i) > min_eigenvalue) inverse_values(i) = 1.0 / values(i);
  }
  const Eigen::MatrixXd H_mm_inverse =
      eigen.eigenvectors() * inverse_values.asDiagonal() * eigen.eigenvectors().transpose();
  LinearSystem out;
  out.H = H_kk - H_km * H_mm_inverse * H_km.transpose();
  out.H = 0.5 * (out.H + out.H.transpose());
  out.b = Select(system.b, keep) - H_km * H_mm_inverse * Select(system.b, marginalize);
  return out;
}

core::Result<SqrtPrior> SqrtPriorFromSystem(const LinearSystem& system, double min_eigenvalue) {
  if (!system.H.allFinite() || !system.b.allFinite()) {
    return core::Status::Error("marginal prior: the linear system has a non-finite entry");
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 *
                                                             (system.H + system.H.transpose()));
  const Eigen::VectorXd& values = eigen.eigenvalues();
  if (values.size() > 0 && values.minCoeff() < -min_eigenvalue * std::max(1.0, values.maxCoeff())) {
    std::ostringstream message;
    message << "marginal prior: information is not positive semi-definite (eigenvalue "
            << values.minCoeff() << ")";
    return core::Status::Error(message.str());
  }
  const int n = static_cast<int>(values.size());
  Eigen::VectorXd sqrt_values = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd inverse_sqrt_values = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) {
    if (values(i) > min_eigenvalue) {
      sqrt_values(i) = std::sqrt(values(i));
      inverse_sqrt_values(i) = 1.0 / sqrt_values(i);
    }
  }
  const Eigen::MatrixXd Vt = eigen.eigenvectors().transpose();
  SqrtPrior prior;
  prior.J = sqrt_values.asDiagonal() * Vt;
  prior.r = inverse_sqrt_values.asDiagonal() * (Vt * system.b);
  return prior;
}

core::Result<LinearSystem> LinearizeFactors(std::span<const LinearizationVariable> variables,
                                            std::span<const LinearizationFactor> factors) {
  std::vector<int> offsets(variables.size() + 1, 0);
  for (size_t i = 0; i < variables.size(); ++i) {
    offsets[i + 1] = offsets[i] + variables[i].TangentSize();
  }
  const int n = offsets.back();
  LinearSystem system{Eigen::MatrixXd::Zero(n, n), Eigen::VectorXd::Zero(n)};
  for (size_t f = 0; f < factors.size(); ++f) {
    const LinearizationFactor& factor = factors[f];
    const int m = factor.cost->num_residuals();
    std::vector<const double*> parameters;
    std::vector<RowMajorMatrix> jacobians;
    std::vector<double*> jacobian_pointers;
    for (const int v : factor.variables) {
      parameters.push_back(variables[v].values);
      jacobians.emplace_back(m, variables[v].size);
      jacobian_pointers.push_back(jacobians.back().data());
    }
    Eigen::VectorXd r(m);
    if (!factor.cost->Evaluate(parameters.data(), r.data(), jacobian_pointers.data())) {
      return core::Status::Error("linearization: factor " + std::to_string(f) +
                                 " failed to evaluate");
    }
    double weight = 1.0;
    if (factor.loss != nullptr) {
      double rho[3];
      factor.loss->Evaluate(r.squaredNorm(), rho);
      weight = std::sqrt(std::max(rho[1], 0.0));
    }
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, n);
    for (size_t k = 0; k < factor.variables.size(); ++k) {
      const LinearizationVariable& variable = variables[factor.variables[k]];
      const Eigen::MatrixXd J_ambient = jacobians[k];
      J.middleCols(offsets[factor.variables[k]], variable.size) +=
          variable.is_pose ? TangentFromAmbientPose(J_ambient, variable.values[2]) : J_ambient;
    }
    if (!r.allFinite() || !J.allFinite()) {
      return core::Status::Error("linearization: factor " + std::to_string(f) +
                                 " returned a non-finite residual or Jacobian");
    }
    J *= weight;
    r *= weight;
    system.H.noalias() += J.transpose() * J;
    system.b.noalias() += J.transpose() * r;
  }
  return system;
}

MarginalPriorFactor::MarginalPriorFactor(MarginalPrior prior) : prior_(std::move(prior)) {
  assert(prior_.x0.size() == prior_.is_pose.size());
  int offset = 0;
  for (const std::vector<double>& x0 : prior_.x0) {
    offsets_.push_back(offset);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(x0.size()));
    offset += static_cast<int>(x0.size());
  }
  assert(offset == prior_.TangentDimension());
  set_num_residuals(offset);
}

bool MarginalPriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                   double** jacobians) const {
  const int n = prior_.TangentDimension();
  Eigen::VectorXd delta(n);
  std::vector<Eigen::MatrixXd> J_delta(prior_.x0.size());
  for (size_t i = 0; i < prior_.x0.size(); ++i) {
    const std::vector<double>& x0 = prior_.x0[i];
    const double* x = parameters[i];
    if (prior_.is_pose[i]) {
      core::Matrix3 J;
      delta.segment<3>(offsets_[i]) =
          core::SE2(x[0], x[1], x[2]).Minus(core::SE2(x0[0], x0[1], x0[2]), &J);
      J_delta[i] = J;
    } else {
      const int size = static_cast<int>(x0.size());
      for (int j = 0; j < size; ++j) delta(offsets_[i] + j) = x[j] - x0[j];
      J_delta[i] = Eigen::MatrixXd::Identity(size, size);
    }
  }
  const SqrtPrior& sqrt_prior = prior_.sqrt_prior;
  Eigen::Map<Eigen::VectorXd>(residuals, n) = sqrt_prior.r + sqrt_prior.J * delta;
  if (jacobians == nullptr) return true;
  for (size_t i = 0; i < prior_.x0.size(); ++i) {
    if (jacobians[i] == nullptr) continue;
    const int size = static_cast<int>(prior_.x0[i].size());
    Eigen::MatrixXd J_tangent = sqrt_prior.J.middleCols(offsets_[i], size) * J_delta[i];
    Eigen::Map<RowMajorMatrix>(jacobians[i], n, size) =
        prior_.is_pose[i]
            ? Eigen::MatrixXd(AmbientFromTangentJacobianRows(J_tangent, parameters[i][2]))
            : J_tangent;
  }
  return true;
}

}  // namespace groundline::localization
