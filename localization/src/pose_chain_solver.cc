#include "groundline/localization/pose_chain_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>

namespace groundline::localization {

PoseChainSystem::PoseChainSystem(int n)
    : diagonal(n, core::Matrix3::Zero()),
      upper(n > 0 ? n - 1 : 0, core::Matrix3::Zero()),
      gradient(n, core::Vector3::Zero()) {}

namespace {

// Forward elimination from `start` on (the blocks before it taken from
// *elimination): the Cholesky factor of S_i per pose, y_i (when with_y) and
// the last S.
core::Status Eliminate(const PoseChainSystem& system, int start, bool with_y,
                       PoseChainElimination* elimination, core::Matrix3* last) {
  const int n = system.size();
  assert(n >= 1);
  assert(static_cast<int>(system.upper.size()) == n - 1);
  assert(static_cast<int>(system.gradient.size()) == n);
  std::vector<Eigen::LLT<core::Matrix3>>& factors = elimination->factors;
  std::vector<core::Vector3>& y = elimination->y;
  start = std::clamp(start, 0, std::min<int>(n - 1, static_cast<int>(factors.size())));
  if (with_y) start = std::min<int>(start, static_cast<int>(y.size()));
  factors.resize(n);
  if (with_y) y.resize(n);
  core::Matrix3 S = core::Matrix3::Zero();
  for (int i = start; i < n; ++i) {
    if (i == 0) {
      S = system.diagonal[0];
      if (with_y) y[0] = system.gradient[0];
    } else {
      const core::Matrix3& U = system.upper[i - 1];
      // U' S_{i-1}^-1 U and U' S_{i-1}^-1 y_{i-1}.
      const core::Matrix3 S_inv_U = factors[i - 1].solve(U);
      S = system.diagonal[i] - U.transpose() * S_inv_U;
      if (with_y) y[i] = system.gradient[i] - S_inv_U.transpose() * y[i - 1];
    }
    S = 0.5 * (S + S.transpose());
    factors[i].compute(S);
    if (!S.allFinite() || factors[i].info() != Eigen::Success) {
      factors.resize(i);
      return core::Status::Error("pose chain: the information of pose " + std::to_string(i) +
                                 " of " + std::to_string(n) +
                                 " is not positive definite given the poses before it");
    }
  }
  *last = S;
  return core::Status::Ok();
}

}  // namespace

core::Result<core::Matrix3> PoseChainLastInformation(const PoseChainSystem& system,
                                                     int first_changed,
                                                     PoseChainElimination* elimination) {
  core::Matrix3 last;
  const core::Status status = Eliminate(system, first_changed, false, elimination, &last);
  if (!status.ok()) return status;
  return last;
}

core::Result<core::Matrix3> PoseChainLastInformation(const PoseChainSystem& system) {
  PoseChainElimination elimination;
  return PoseChainLastInformation(system, 0, &elimination);
}

core::Result<PoseChainStep> SolvePoseChain(const PoseChainSystem& system) {
  PoseChainElimination elimination;
  return SolvePoseChain(system, 0, &elimination);
}

core::Result<PoseChainStep> SolvePoseChain(const PoseChainSystem& system, int first_changed,
                                           PoseChainElimination* elimination) {
  const int n = system.size();
  PoseChainStep step;
  const core::Status status =
      Eliminate(system, first_changed, true, elimination, &step.last_information);
  if (!status.ok()) return status;
  const std::vector<Eigen::LLT<core::Matrix3>>& factors = elimination->factors;
  const std::vector<core::Vector3>& y = elimination->y;
  step.delta.resize(n);
  step.delta[n - 1] = -factors[n - 1].solve(y[n - 1]);
  for (int i = n - 2; i >= 0; --i) {
    step.delta[i] = -factors[i].solve(y[i] + system.upper[i] * step.delta[i + 1]);
  }
  return step;
}

}  // namespace groundline::localization
