#include "groundline/localization/pose_chain_solver.h"

#include <Eigen/Cholesky>
#include <cassert>

namespace groundline::localization {

PoseChainSystem::PoseChainSystem(int n)
    : diagonal(n, core::Matrix3::Zero()),
      upper(n > 0 ? n - 1 : 0, core::Matrix3::Zero()),
      gradient(n, core::Vector3::Zero()) {}

namespace {

// Forward elimination: the Cholesky factor of S_i per pose, y_i (when y is
// given) and the last S.
core::Status Eliminate(const PoseChainSystem& system,
                       std::vector<Eigen::LLT<core::Matrix3>>* factors,
                       std::vector<core::Vector3>* y, core::Matrix3* last) {
  const int n = system.size();
  assert(n >= 1);
  assert(static_cast<int>(system.upper.size()) == n - 1);
  assert(static_cast<int>(system.gradient.size()) == n);
  factors->resize(n);
  if (y != nullptr) {
    y->resize(n);
    (*y)[0] = system.gradient[0];
  }
  core::Matrix3 S = system.diagonal[0];
  for (int i = 0; i < n; ++i) {
    if (i > 0) {
      const core::Matrix3& U = system.upper[i - 1];
      // U' S_{i-1}^-1 U and U' S_{i-1}^-1 y_{i-1}.
      const core::Matrix3 S_inv_U = (*factors)[i - 1].solve(U);
      S = system.diagonal[i] - U.transpose() * S_inv_U;
      if (y != nullptr) (*y)[i] = system.gradient[i] - S_inv_U.transpose() * (*y)[i - 1];
    }
    S = 0.5 * (S + S.transpose());
    (*factors)[i].compute(S);
    if (!S.allFinite() || (*factors)[i].info() != Eigen::Success) {
      return core::Status::Error("pose chain: the information of pose " + std::to_string(i) +
                                 " of " + std::to_string(n) +
                                 " is not positive definite given the poses before it");
    }
  }
  *last = S;
  return core::Status::Ok();
}

}  // namespace

core::Result<core::Matrix3> PoseChainLastInformation(const PoseChainSystem& system) {
  std::vector<Eigen::LLT<core::Matrix3>> factors;
  core::Matrix3 last;
  const core::Status status = Eliminate(system, &factors, nullptr, &last);
  if (!status.ok()) return status;
  return last;
}

core::Result<PoseChainStep> SolvePoseChain(const PoseChainSystem& system) {
  const int n = system.size();
  std::vector<Eigen::LLT<core::Matrix3>> factors;
  std::vector<core::Vector3> y;
  PoseChainStep step;
  const core::Status status = Eliminate(system, &factors, &y, &step.last_information);
  if (!status.ok()) return status;
  step.delta.resize(n);
  step.delta[n - 1] = -factors[n - 1].solve(y[n - 1]);
  for (int i = n - 2; i >= 0; --i) {
    step.delta[i] = -factors[i].solve(y[i] + system.upper[i] * step.delta[i + 1]);
  }
  return step;
}

}  // namespace groundline::localization
