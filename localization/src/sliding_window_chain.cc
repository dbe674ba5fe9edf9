// The localization-mode window solve of SlidingWindowSmoother as a pose chain
// (pose_chain_solver.h): Gauss-Newton from the previous solution, each
// keyframe's linearized terms kept until its poses move by more than a
// small fraction of the step tolerance, so an update relinearizes and
// re-eliminates only the recent part of the window that the new keyframe
// moved (the rest of the solve is a back-substitution of 3x3 blocks).
#include <ceres/loss_function.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "groundline/core/se2_manifold.h"
#include "groundline/localization/floor_factors.h"
#include "groundline/localization/relative_pose_factor.h"
#include "groundline/localization/sliding_window_smoother.h"

namespace groundline::localization {
namespace {

// Terms are relinearized when a pose moved by more than this fraction of
// the step tolerance (the gradient error it leaves is far below the
// solution's tolerance).
constexpr double kRelinearizeFraction = 1e-3;
// A step whose largest component is below this many step tolerances and
// that raises the cost ends the solve on the poses before it.
constexpr double kNoiseFloorSteps = 100.0;

// Kept terms are evaluated within the relinearization tolerance of the
// poses, so costs are compared with a margin.
bool Uphill(double cost, double previous_cost) {
  return !(cost <= previous_cost + 1e-9 * std::abs(previous_cost) + 1e-12);
}

bool Moved(const std::array<double, 3>& x, const std::array<double, 3>& at, double tolerance) {
  return std::abs(x[0] - at[0]) > tolerance || std::abs(x[1] - at[1]) > tolerance ||
         std::abs(x[2] - at[2]) > tolerance;
}

// Adds one residual r with pose Jacobian J under the loss rho(s), s = |r|^2;
// returns 0.5 rho(s). The gradient is rho' J^T r. Two Hessians:
//  - *information, the reweighted rho' J^T J (iteratively reweighted least
//    squares, Ceres' model for a loss with rho'' < 0; corrector.cc): the
//    covariance, the marginal prior, and the safe step. For a loss concave
//    in s it lies above the loss, so its step does not overshoot;
//  - *H, Newton's: plus the curvature term 2 rho'' J^T r r^T J while it
//    leaves the curvature along r positive. Near the solution it converges
//    quadratically where the reweighted model is linear (3 iterations vs 6
//    at the median of BM_KeyframeUpdate), but in the tail of a bending loss
//    it is nearly flat along r (SoftLOne: (1 + s/c^2)^-3/2) and, when that
//    residual dominates its direction, overshoots by ~(1 + s/c^2): Newton on
//    a pseudo-Huber cost alone diverges beyond |r| = c. SolveChain takes
//    Newton steps while they descend, then the reweighted ones.
template <int M>
double AddUnary(const Eigen::Matrix<double, M, 1>& r, const Eigen::Matrix<double, M, 3>& J,
                const ceres::LossFunction* loss, core::Matrix3* H, core::Matrix3* information,
                core::Vector3* b) {
  const double s = r.squaredNorm();
  double rho[3] = {s, 1.0, 0.0};
  if (loss != nullptr) loss->Evaluate(s, rho);
  const double w = std::max(rho[1], 0.0);
  const core::Matrix3 JtJ = J.transpose() * J;
  const core::Vector3 Jtr = J.transpose() * r;
  H->noalias() += w * JtJ;
  information->noalias() += w * JtJ;
  if (w + 2.0 * rho[2] * s > 0.0) H->noalias() += 2.0 * rho[2] * Jtr * Jtr.transpose();
  b->noalias() += w * Jtr;
  return 0.5 * rho[0];
}

}  // namespace

void SlidingWindowSmoother::InvalidateChain() {
  chain_.system_clean = 0;
  chain_.step_clean = 0;
  chain_.newest_clean = 0;
  ++prior_version_;
}

void SlidingWindowSmoother::LinearizePrior() {
  // r = r0 + J Log(x0^-1 x), dr/dx = J Jr^-1 (MarginalPriorFactor).
  const MarginalPrior& prior = prior_->prior();
  const core::SE2 x0(prior.x0[0][0], prior.x0[0][1], prior.x0[0][2]);
  core::Matrix3 J_delta;
  const core::Vector3 delta = core::PoseFromAmbient(window_[0].pose).Minus(x0, &J_delta);
  const core::Vector3 r = prior.sqrt_prior.r + prior.sqrt_prior.J * delta;
  const core::Matrix3 J = prior.sqrt_prior.J * J_delta;
  ChainTerms terms;
  terms.valid = true;
  terms.at = window_[0].pose;
  terms.prior_version = prior_version_;
  terms.cost = AddUnary<3>(r, J, nullptr, &terms.H_unary, &terms.information_unary, &terms.b_unary);
  chain_.prior = terms;
}

void SlidingWindowSmoother::LinearizeKeyframe(int index) {
  Keyframe& keyframe = window_[index];
  ChainTerms terms;
  terms.valid = true;
  terms.at = keyframe.pose;
  const core::SE2 T = core::PoseFromAmbient(keyframe.pose);
  Eigen::Matrix<double, 2, 3> J;
  for (const auto& factor : keyframe.lines) {
    const std::array<double, 2>& block = line_blocks_[factor.landmark];
    const Eigen::Vector2d r = factor.cost->Residual(T, {block[0], block[1]}, &J);
    terms.cost += AddUnary<2>(r, J, line_loss_.get(), &terms.H_unary, &terms.information_unary,
                              &terms.b_unary);
  }
  for (const auto& factor : keyframe.junctions) {
    const std::array<double, 2>& block = junction_blocks_[factor.landmark];
    const Eigen::Vector2d r = factor.cost->Residual(T, {block[0], block[1]}, &J);
    terms.cost += AddUnary<2>(r, J, junction_loss_.get(), &terms.H_unary, &terms.information_unary,
                              &terms.b_unary);
  }
  if (index > 0) {
    terms.at_previous = window_[index - 1].pose;
    const core::SE2 T_previous = core::PoseFromAmbient(terms.at_previous);
    for (const auto& between : keyframe.between) {
      core::Matrix3 J_a;
      core::Matrix3 J_b;
      const core::Vector3 r = between->Residual(T_previous, T, &J_a, &J_b);
      terms.H_previous.noalias() += J_a.transpose() * J_a;
      terms.H_cross.noalias() += J_a.transpose() * J_b;
      terms.H_current.noalias() += J_b.transpose() * J_b;
      terms.b_previous.noalias() += J_a.transpose() * r;
      terms.b_current.noalias() += J_b.transpose() * r;
      terms.cost += 0.5 * r.squaredNorm();
    }
  }
  keyframe.chain = terms;
}

double SlidingWindowSmoother::LinearizeChain(bool relinearize_all) {
  const int n = static_cast<int>(window_.size());
  const double tolerance = kRelinearizeFraction * options_.step_tolerance;
  int first_changed = std::min(chain_.system_clean, n);
  const ChainTerms& prior = chain_.prior;
  if (relinearize_all || !prior.valid || prior.prior_version != prior_version_ ||
      Moved(window_[0].pose, prior.at, tolerance)) {
    LinearizePrior();
    first_changed = 0;
  }
  for (int i = 0; i < n; ++i) {
    const ChainTerms& terms = window_[i].chain;
    if (!relinearize_all && terms.valid && !Moved(window_[i].pose, terms.at, tolerance) &&
        (i == 0 || !Moved(window_[i - 1].pose, terms.at_previous, tolerance))) {
      continue;
    }
    LinearizeKeyframe(i);
    first_changed = std::min(first_changed, std::max(0, i - 1));
  }
  // Assemble the blocks from first_changed on.
  for (PoseChainSystem* system : {&chain_.system, &chain_.information}) {
    system->diagonal.resize(n);
    system->gradient.resize(n);
    system->upper.resize(n - 1);
  }
  for (int i = first_changed; i < n; ++i) {
    const ChainTerms& terms = window_[i].chain;
    core::Matrix3 H = terms.H_unary + terms.H_current;
    core::Matrix3 information = terms.information_unary + terms.H_current;
    core::Vector3 b = terms.b_unary + terms.b_current;
    if (i == 0) {
      H += chain_.prior.H_unary;
      information += chain_.prior.information_unary;
      b += chain_.prior.b_unary;
    }
    if (i + 1 < n) {
      const ChainTerms& next = window_[i + 1].chain;
      H += next.H_previous;
      information += next.H_previous;
      b += next.b_previous;
      chain_.system.upper[i] = next.H_cross;
      chain_.information.upper[i] = next.H_cross;
    }
    chain_.system.diagonal[i] = H;
    chain_.information.diagonal[i] = information;
    chain_.system.gradient[i] = b;
    chain_.information.gradient[i] = b;
  }
  chain_.system_clean = n;
  chain_.step_clean = std::min(chain_.step_clean, first_changed);
  chain_.newest_clean = std::min(chain_.newest_clean, first_changed);
  double cost = chain_.prior.cost;
  for (const Keyframe& keyframe : window_) cost += keyframe.chain.cost;
  return cost;
}

core::Status SlidingWindowSmoother::SolveChain(KeyframeHealth* health) {
  const int n = static_cast<int>(window_.size());
  std::vector<std::array<double, 3>> previous(n);
  std::vector<core::Vector3> step;
  double previous_cost = std::numeric_limits<double>::infinity();
  double largest = 0.0;  // the largest component of the last step
  bool converged = false;
  health->iterations = 0;
  // Newton steps (chain_.system) until one raises the cost, then the
  // reweighted ones (chain_.information), which descend.
  bool newton = true;
  while (health->iterations < options_.max_iterations) {
    ++health->iterations;
    const double cost = LinearizeChain(false);
    if (!std::isfinite(cost)) return core::Status::Error("window solve: the cost is not finite");
    if (Uphill(cost, previous_cost)) {
      const bool noise = largest < kNoiseFloorSteps * options_.step_tolerance;
      if (noise || newton) {
        // Back to the poses before the step: at the noise floor of the
        // cost (its kept terms, the stiff odometry) they are the solution;
        // else the solve goes on from them with the reweighted model.
        for (int i = 0; i < n; ++i) window_[i].pose = previous[i];
        converged = noise;
        newton = false;
        if (noise) break;
        continue;
      }
      // A reweighted step went uphill (a nonlinearity): half of it.
      largest *= 0.5;
      for (int i = 0; i < n; ++i) {
        step[i] *= 0.5;
        window_[i].pose = core::AmbientOf(core::PoseFromAmbient(previous[i]).Plus(step[i]));
      }
      continue;
    }
    const auto solution =
        newton ? SolvePoseChain(chain_.system, chain_.step_clean, &chain_.step_elimination)
               : SolvePoseChain(chain_.information);
    if (newton) chain_.step_clean = solution.ok() ? n : 0;
    if (!solution.ok()) return solution.status().WithContext("window solve");
    step = solution->delta;
    largest = 0.0;
    for (int i = 0; i < n; ++i) {
      previous[i] = window_[i].pose;
      const double size = step[i].cwiseAbs().maxCoeff();
      largest = std::max(largest, size);
      if (size > 1e-15)
        window_[i].pose = core::AmbientOf(core::PoseFromAmbient(window_[i].pose).Plus(step[i]));
    }
    previous_cost = cost;
    if (largest < options_.step_tolerance) {
      converged = true;
      break;
    }
  }
  health->converged = converged;
  if (!converged && std::isfinite(previous_cost) && Uphill(LinearizeChain(false), previous_cost)) {
    // The iterations ran out on a step (or its halving) that goes uphill:
    // back to the last poses that did not.
    for (int i = 0; i < n; ++i) window_[i].pose = previous[i];
    LinearizeChain(false);
  }
  // The newest information at the last linearization point (within the last
  // step of the solution).
  const auto newest =
      PoseChainLastInformation(chain_.information, chain_.newest_clean, &chain_.newest_elimination);
  chain_.newest_clean = newest.ok() ? n : 0;
  if (!newest.ok()) return newest.status().WithContext("window solve");
  newest_information_ = *newest;
  newest_information_valid_ = true;
  return core::Status::Ok();
}

}  // namespace groundline::localization
