// The window solve of SlidingWindowSmoother with Ceres (mapping mode, and the
// reference for the chain solver of sliding_window_chain.cc), and the newest
// pose's marginal information.
#include <ceres/ceres.h>

#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "groundline/core/run_timing.h"
#include "groundline/core/se2_manifold.h"
#include "groundline/localization/floor_factors.h"
#include "groundline/localization/pose_chain_solver.h"
#include "groundline/localization/relative_pose_factor.h"
#include "groundline/localization/sliding_window_smoother.h"

namespace groundline::localization {
namespace {

using Clock = std::chrono::steady_clock;

using core::SecondsSince;

const core::SE2Manifold kSe2Manifold;

}  // namespace

std::vector<core::SE2> SlidingWindowSmoother::WindowPoses() const {
  std::vector<core::SE2> poses;
  for (const Keyframe& keyframe : window_) poses.push_back(core::PoseFromAmbient(keyframe.pose));
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
  health->converged = summary.termination_type == ceres::CONVERGENCE;
  if (!summary.IsSolutionUsable()) {
    return core::Status::Error("window solve failed: " + summary.message);
  }
  return core::Status::Ok();
}

core::Result<core::Matrix3> SlidingWindowSmoother::NewestInformation() {
  if (newest_information_valid_) return newest_information_;
  // Mapping mode: the landmarks moved too, so every term is relinearized.
  LinearizeChain(options_.mode == SmootherMode::kMapping);
  const auto newest =
      PoseChainLastInformation(chain_.information, chain_.newest_clean, &chain_.newest_elimination);
  chain_.newest_clean = newest.ok() ? chain_.system.size() : 0;
  if (!newest.ok()) return newest.status().WithContext("newest covariance");
  return *newest;
}

}  // namespace groundline::localization
