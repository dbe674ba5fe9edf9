#include "groundline/localization/pose_chain_solver.h"

#include <Eigen/Cholesky>
#include <cassert>

namespace groundline::localization {

PoseChainSystem::PoseChainSystem(int n)
    : diagonal(n, core::Matrix3::Zero()),
      upper(n > 0 ? n - 1 : 0, core::Matrix3::Zero()),
      gradient(n, core::Vector3::Zero()) {}

core::Result<PoseChainStep> SolvePoseChain(const PoseChainSystem& system) {
  const int n = system.size();
  assert(n >= 1);
  assert(static_cast<int>(system.upper.size()) == n - 1);
  assert(static_cast<int>(system.gradient.size()) == n);
  // Forward elimination: the factor of S_i and y_i per pose.
  std::vector<Eigen::LLT<core::Matrix3>> factors(n);
  std::vector<core::Vector3> y(n);
  core::Matrix3 S = system.diagonal[0];
  y[0] = system.gradient[0];
  for (int i = 0; i < n; ++i) {
    if (i > 0) {
      const core::Matrix3& U = system.upper[i - 1];
      // U' S_{i-1}^-1 U and U' S_{i-1}^-1 y_{i-1}.
      const core::Matrix3 S_inv_U = factors[i - 1].solve(U);
      S = system.diagonal[i] - U.transpose() * S_inv_U;
      y[i] = system.gradient[i] - S_inv_U.transpose() * y[i - 1];
    }
    S = 0.5 * (S + S.transpose());
    factors[i].compute(S);
    if (!S.allFinite() || factors[i].info() != Eigen::Success) {
      return core::Status::Error("pose chain: the information of pose " + std::to_string(i) +
                                 " of " + std::to_string(n) +
                                 " is not positive definite given the poses before it");
    }
  }
  PoseChainStep step;
  step.last_information = S;
  step.delta.resize(n);
  step.delta[n - 1] = -factors[n - 1].solve(y[n - 1]);
  for (int i = n - 2; i >= 0; --i) {
    step.delta[i] = -factors[i].solve(y[i] + system.upper[i] * step.delta[i + 1]);
  }
  return step;
}

}  // namespace groundline::localization
