// The Gauss-Newton normal equations of an SE(2) pose chain, solved exactly in
// O(n) by block forward elimination and back-substitution (the
// Rauch-Tung-Striebel form of a smoother).
//
// In localization mode the landmarks are fixed, so every factor of the
// sliding window touches one pose (the marginal prior on the oldest pose,
// line and junction factors) or two consecutive poses (odometry and other
// relative measurements). The normal matrix H = J^T J in the stacked tangent
// coordinates of the poses is then block tridiagonal with 3x3 blocks:
//   H = [D_0  U_0                ]
//       [U_0' D_1  U_1           ]
//       [     U_1' D_2  ...      ]
// and H delta = -b is solved by eliminating the poses oldest first:
//   S_0 = D_0,               y_0 = b_0,
//   S_i = D_i - U_{i-1}' S_{i-1}^-1 U_{i-1},   y_i = b_i - U_{i-1}' S_{i-1}^-1 y_{i-1},
//   delta_{n-1} = -S_{n-1}^-1 y_{n-1},
//   delta_i = -S_i^-1 (y_i + U_i delta_{i+1}).
// S_i is the information of pose i given everything up to it (the filter);
// the last one, S_{n-1}, is the marginal information of the newest pose over
// the whole chain (its covariance is S_{n-1}^-1), so the newest covariance
// needs no second sweep.
//
// Pure functions, thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_POSE_CHAIN_SOLVER_H_
#define GROUNDLINE_LOCALIZATION_POSE_CHAIN_SOLVER_H_

#include <Eigen/Cholesky>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::localization {

struct PoseChainSystem {
  std::vector<core::Matrix3> diagonal;  // D_i = H_ii, n blocks
  std::vector<core::Matrix3> upper;     // U_i = H_{i,i+1}, n - 1 blocks
  std::vector<core::Vector3> gradient;  // b_i, n blocks (the gradient J^T r)

  // n zero blocks.
  explicit PoseChainSystem(int n = 0);
  int size() const { return static_cast<int>(diagonal.size()); }
};

struct PoseChainStep {
  std::vector<core::Vector3> delta;                        // H delta = -b, per pose
  core::Matrix3 last_information = core::Matrix3::Zero();  // S_{n-1}
};

// The forward elimination of a system, kept to be reused: when only the
// blocks from index k on change (a new keyframe, the poses near the newest
// relinearized), S_i and y_i for i < k are still valid.
struct PoseChainElimination {
  std::vector<Eigen::LLT<core::Matrix3>> factors;  // Cholesky of S_i
  std::vector<core::Vector3> y;
};

// The Gauss-Newton step of the system (n >= 1, the blocks sized as above:
// asserted). Fails when some S_i is not positive definite (a pose with no
// information about some direction, given the poses before it) or not finite.
core::Result<PoseChainStep> SolvePoseChain(const PoseChainSystem& system);
// The same, eliminating only from `first_changed` on: *elimination must hold
// the elimination of a system whose blocks before first_changed (diagonal i,
// the diagonal, gradient and upper blocks with index < first_changed) equal
// this one's; it is updated to this system's.
core::Result<PoseChainStep> SolvePoseChain(const PoseChainSystem& system, int first_changed,
                                           PoseChainElimination* elimination);

// Only the forward elimination: S_{n-1}, the marginal information of the last
// pose (the gradient is not used). Fails as SolvePoseChain.
core::Result<core::Matrix3> PoseChainLastInformation(const PoseChainSystem& system);
core::Result<core::Matrix3> PoseChainLastInformation(const PoseChainSystem& system,
                                                     int first_changed,
                                                     PoseChainElimination* elimination);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_POSE_CHAIN_SOLVER_H_
