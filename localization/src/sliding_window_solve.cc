// The window solve of SlidingWindowSmoother: the chain solver (localization
// mode) and Ceres (mapping mode, and the reference), and the newest pose's
// marginal information.
#include <ceres/ceres.h>

#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "groundline/core/se2_manifold.h"
#include "groundline/localization/floor_factors.h"
#include "groundline/localization/pose_chain_solver.h"
#include "groundline/localization/relative_pose_factor.h"
#include "groundline/localization/sliding_window_smoother.h"

namespace groundline::localization {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

core::SE2 PoseOf(const std::array<double, 3>& x) { return core::SE2(x[0], x[1], x[2]); }
std::array<double, 3> ArrayOf(const core::SE2& T) { return {T.x(), T.y(), T.yaw()}; }

const core::SE2Manifold kSe2Manifold;

// Adds one residual r with pose Jacobian J under the loss rho(s), s = |r|^2,
// to the normal equations; returns 0.5 rho(s). The gradient is rho' J^T r.
// The solve Hessian is the Gauss-Newton Hessian of the robust cost,
// J^T (rho' I + 2 rho'' r r^T) J, whose second term (negative for SoftLOne)
// makes the step Newton-like in the loss (iteratively reweighted least
// squares alone, rho' J^T J, converges only linearly, by 1 - (1 + s/c^2)^-1
// per iteration); it is used while positive definite along r, else the
// reweighted one (as Ceres' corrector clamps it). The information (for the
// covariance and the marginal prior) is the reweighted rho' J^T J.
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

std::vector<core::SE2> SlidingWindowSmoother::WindowPoses() const {
  std::vector<core::SE2> poses;
  for (const Keyframe& keyframe : window_) poses.push_back(PoseOf(keyframe.pose));
  return poses;
}

core::Status SlidingWindowSmoother::Solve(KeyframeHealth* health) {
  newest_information_valid_ = false;
  const Clock::time_point start = Clock::now();
  const bool chain =
      options_.mode == SmootherMode::kLocalization && options_.solver == SmootherSolver::kChain;
  core::Status status = chain ? SolveChain(health) : SolveCeres(health);
  health->solve_time_s = SecondsSince(start);
  return status;
}

double SlidingWindowSmoother::LinearizeChain(PoseChainSystem* system,
                                             PoseChainSystem* information) const {
  const int n = static_cast<int>(window_.size());
  *system = PoseChainSystem(n);
  std::vector<core::Matrix3> information_diagonal(n, core::Matrix3::Zero());
  double cost = 0.0;
  // The marginal prior on the oldest pose: r = r0 + J Log(x0^-1 x).
  const MarginalPrior& prior = prior_->prior();
  const core::SE2 x0(prior.x0[0][0], prior.x0[0][1], prior.x0[0][2]);
  core::Matrix3 J_delta;
  const core::Vector3 delta = PoseOf(window_[0].pose).Minus(x0, &J_delta);
  const core::Vector3 r_prior = prior.sqrt_prior.r + prior.sqrt_prior.J * delta;
  const core::Matrix3 J_prior = prior.sqrt_prior.J * J_delta;
  cost += AddUnary<3>(r_prior, J_prior, nullptr, &system->diagonal[0], &information_diagonal[0],
                      &system->gradient[0]);
  for (int i = 0; i < n; ++i) {
    const Keyframe& keyframe = window_[i];
    const core::SE2 T = PoseOf(keyframe.pose);
    core::Matrix3& D = system->diagonal[i];
    core::Vector3& b = system->gradient[i];
    Eigen::Matrix<double, 2, 3> J;
    for (const auto& factor : keyframe.lines) {
      const std::array<double, 2>& block = line_blocks_[factor.landmark];
      const Eigen::Vector2d r = factor.cost->Residual(T, {block[0], block[1]}, &J);
      cost += AddUnary<2>(r, J, line_loss_.get(), &D, &information_diagonal[i], &b);
    }
    for (const auto& factor : keyframe.junctions) {
      const std::array<double, 2>& block = junction_blocks_[factor.landmark];
      const Eigen::Vector2d r = factor.cost->Residual(T, {block[0], block[1]}, &J);
      cost += AddUnary<2>(r, J, junction_loss_.get(), &D, &information_diagonal[i], &b);
    }
    if (i == 0) continue;
    const core::SE2 T_prev = PoseOf(window_[i - 1].pose);
    for (const auto& between : keyframe.between) {
      core::Matrix3 J_a;
      core::Matrix3 J_b;
      const core::Vector3 r = between->Residual(T_prev, T, &J_a, &J_b);
      const core::Matrix3 JtJ_a = J_a.transpose() * J_a;
      const core::Matrix3 JtJ_b = J_b.transpose() * J_b;
      system->diagonal[i - 1] += JtJ_a;
      information_diagonal[i - 1] += JtJ_a;
      system->upper[i - 1].noalias() += J_a.transpose() * J_b;
      D += JtJ_b;
      information_diagonal[i] += JtJ_b;
      system->gradient[i - 1].noalias() += J_a.transpose() * r;
      b.noalias() += J_b.transpose() * r;
      cost += 0.5 * r.squaredNorm();
    }
  }
  if (information != nullptr) {
    information->diagonal = std::move(information_diagonal);
    information->upper = system->upper;
    information->gradient = system->gradient;
  }
  return cost;
}

core::Status SlidingWindowSmoother::SolveChain(KeyframeHealth* health) {
  const int n = static_cast<int>(window_.size());
  PoseChainSystem system;
  PoseChainSystem information;
  std::vector<std::array<double, 3>> previous(n);
  std::vector<core::Vector3> step;
  double previous_cost = std::numeric_limits<double>::infinity();
  health->iterations = 0;
  while (health->iterations < options_.max_iterations) {
    ++health->iterations;
    const double cost = LinearizeChain(&system, &information);
    if (!std::isfinite(cost)) return core::Status::Error("window solve: the cost is not finite");
    if (cost > previous_cost + 1e-12 * std::abs(previous_cost)) {
      // The last step went uphill (a nonlinearity or a reweighting): half of it.
      for (int i = 0; i < n; ++i) {
        step[i] *= 0.5;
        window_[i].pose = ArrayOf(PoseOf(previous[i]).Plus(step[i]));
      }
      continue;
    }
    const auto solution = SolvePoseChain(system);
    if (!solution.ok()) return solution.status().WithContext("window solve");
    step = solution->delta;
    double largest = 0.0;
    for (int i = 0; i < n; ++i) {
      previous[i] = window_[i].pose;
      window_[i].pose = ArrayOf(PoseOf(window_[i].pose).Plus(step[i]));
      largest = std::max(largest, step[i].cwiseAbs().maxCoeff());
    }
    previous_cost = cost;
    if (largest < options_.step_tolerance) break;
  }
  // The newest information at the last linearization point (within the last
  // step of the solution).
  const auto newest = PoseChainLastInformation(information);
  if (!newest.ok()) return newest.status().WithContext("window solve");
  newest_information_ = *newest;
  newest_information_valid_ = true;
  return core::Status::Ok();
}

core::Status SlidingWindowSmoother::SolveCeres(KeyframeHealth* health) {
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  auto* manifold = const_cast<core::SE2Manifold*>(&kSe2Manifold);
  for (Keyframe& keyframe : window_) problem.AddParameterBlock(keyframe.pose.data(), 3, manifold);
  problem.AddResidualBlock(prior_.get(), nullptr, window_.front().pose.data());
  const bool mapping = options_.mode == SmootherMode::kMapping;
  const auto add_landmark = [&](ceres::CostFunction* cost, ceres::LossFunction* loss, double* pose,
                                double* block) {
    problem.AddResidualBlock(cost, loss, pose, block);
    if (!mapping) problem.SetParameterBlockConstant(block);
  };
  for (size_t i = 0; i < window_.size(); ++i) {
    Keyframe& keyframe = window_[i];
    for (auto& between : keyframe.between) {
      problem.AddResidualBlock(between.get(), nullptr, window_[i - 1].pose.data(),
                               keyframe.pose.data());
    }
    for (auto& factor : keyframe.lines) {
      add_landmark(factor.cost.get(), line_loss_.get(), keyframe.pose.data(),
                   line_blocks_[factor.landmark].data());
    }
    for (auto& factor : keyframe.junctions) {
      add_landmark(factor.cost.get(), junction_loss_.get(), keyframe.pose.data(),
                   junction_blocks_[factor.landmark].data());
    }
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.num_threads = 1;
  options.max_num_iterations = options_.max_iterations;
  // Ceres' defaults (1e-6, 1e-8, 1e-10) unless a tighter tolerance is asked for.
  options.function_tolerance = options_.ceres_tolerance;
  options.parameter_tolerance = std::min(1e-8, options_.ceres_tolerance);
  options.gradient_tolerance = std::min(1e-10, options_.ceres_tolerance);
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  health->iterations = static_cast<int>(summary.iterations.size());
  if (!summary.IsSolutionUsable()) {
    return core::Status::Error("window solve failed: " + summary.message);
  }
  return core::Status::Ok();
}

core::Result<core::Matrix3> SlidingWindowSmoother::NewestInformation() const {
  if (newest_information_valid_) return newest_information_;
  PoseChainSystem system;
  PoseChainSystem information;
  LinearizeChain(&system, &information);
  const auto newest = PoseChainLastInformation(information);
  if (!newest.ok()) return newest.status().WithContext("newest covariance");
  return *newest;
}

}  // namespace groundline::localization
