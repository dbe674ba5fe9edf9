// Schur marginalization, tested differentially: marginalizing and then
// solving equals solving the full problem and dropping the variables, on a
// linear-Gaussian system and on SE(2) pose chains solved with Ceres; the
// square-root prior reproduces (H, b); the prior factor's Jacobians match
// numeric differentiation.
#include "groundline/localization/marginalization.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <numeric>
#include <random>

#include "groundline/core/random_draws.h"
#include "groundline/core/se2_manifold.h"
#include "groundline/localization/floor_factors.h"
#include "groundline/localization/relative_pose_factor.h"
#include "jacobian_check.h"

namespace groundline::localization {
namespace {

using core::SE2;

TEST(MarginalizeSchur, MarginalizeThenSolveEqualsSolveThenDrop) {
  std::mt19937 rng(31);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd J(20, 9);
  Eigen::VectorXd r(20);
  for (int i = 0; i < J.size(); ++i) J(i) = normal(rng);
  for (int i = 0; i < r.size(); ++i) r(i) = normal(rng);
  const LinearSystem full{J.transpose() * J, J.transpose() * r};
  const Eigen::VectorXd dx_full = full.H.ldlt().solve(-full.b);

  const std::vector<int> keep = {7, 0, 1, 2, 5, 4};  // any order
  const std::vector<int> marginalize = {3, 6, 8};
  const LinearSystem reduced = MarginalizeSchur(full, keep, marginalize).value();
  const Eigen::VectorXd dx_reduced = reduced.H.ldlt().solve(-reduced.b);
  for (size_t i = 0; i < keep.size(); ++i) EXPECT_NEAR(dx_reduced(i), dx_full(keep[i]), 1e-9);

  // The marginal covariance is the kept block of the full covariance.
  const Eigen::MatrixXd covariance_full = full.H.inverse();
  const Eigen::MatrixXd covariance_reduced = reduced.H.inverse();
  for (size_t i = 0; i < keep.size(); ++i) {
    for (size_t j = 0; j < keep.size(); ++j) {
      EXPECT_NEAR(covariance_reduced(i, j), covariance_full(keep[i], keep[j]), 1e-9);
    }
  }

  const SqrtPrior prior = SqrtPriorFromSystem(reduced).value();
  EXPECT_LT((prior.J.transpose() * prior.J - reduced.H).norm(), 1e-9 * reduced.H.norm());
  EXPECT_LT((prior.J.transpose() * prior.r - reduced.b).norm(), 1e-9 * reduced.b.norm());
}

TEST(MarginalizeSchur, RejectsNonFiniteAndNonPsdSystems) {
  LinearSystem bad{Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2)};
  bad.H(0, 0) = std::nan("");
  EXPECT_FALSE(MarginalizeSchur(bad, std::vector<int>{0}, std::vector<int>{1}).ok());
  LinearSystem not_psd{-Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2)};
  EXPECT_FALSE(SqrtPriorFromSystem(not_psd).ok());
}

// A chain of 6 poses: a prior on x0, odometry between neighbours, loose
// absolute fixes on x2 and x5. Marginalizing x0, x1 into a prior on x2 and
// solving x2..x5 must give the full solution.
struct Chain {
  std::vector<SE2> truth;
  std::vector<SE2> odometry;  // T_i_i+1 measured
  std::array<SE2, 2> fixes;   // on x2 and x5
  Eigen::Matrix3d odom_sqrt = Eigen::Vector3d(20.0, 40.0, 50.0).asDiagonal();
  Eigen::Matrix3d fix_sqrt = Eigen::Vector3d(5.0, 5.0, 10.0).asDiagonal();
  Eigen::Matrix3d prior_sqrt = Eigen::Matrix3d::Identity() * 100.0;

  explicit Chain(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.03);
    truth.push_back(SE2(1.0, 2.0, 0.3));
    for (int i = 1; i < 6; ++i) truth.push_back(truth.back() * SE2(1.0, 0.1, 0.35));
    for (int i = 0; i < 5; ++i) {
      const Eigen::Vector3d n = core::DrawVector<3>(noise, rng);
      odometry.push_back(truth[i].Between(truth[i + 1]) * SE2(n(0), n(1), n(2)));
    }
    fixes[0] = truth[2] * SE2(0.1, -0.05, 0.04);
    fixes[1] = truth[5] * SE2(-0.08, 0.12, -0.05);
  }

  // Dead-reckoned initial values.
  std::vector<std::array<double, 3>> Initial() const {
    std::vector<std::array<double, 3>> x;
    SE2 T = truth[0];
    for (int i = 0; i < 6; ++i) {
      x.push_back({T.x(), T.y(), T.yaw()});
      if (i < 5) T = T * odometry[i];
    }
    return x;
  }
};

void Solve(ceres::Problem* problem) {
  ceres::Solver::Options options;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-15;
  options.gradient_tolerance = 1e-15;
  options.parameter_tolerance = 1e-15;
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
}

std::vector<std::array<double, 3>> SolveFull(const Chain& chain) {
  std::vector<std::array<double, 3>> x = chain.Initial();
  ceres::Problem problem;
  for (auto& pose : x) problem.AddParameterBlock(pose.data(), 3, new core::SE2Manifold);
  problem.AddResidualBlock(new PosePriorFactor(chain.truth[0], chain.prior_sqrt), nullptr,
                           x[0].data());
  for (int i = 0; i < 5; ++i) {
    problem.AddResidualBlock(new RelativePoseFactor(chain.odometry[i], chain.odom_sqrt), nullptr,
                             x[i].data(), x[i + 1].data());
  }
  problem.AddResidualBlock(new PosePriorFactor(chain.fixes[0], chain.fix_sqrt), nullptr,
                           x[2].data());
  problem.AddResidualBlock(new PosePriorFactor(chain.fixes[1], chain.fix_sqrt), nullptr,
                           x[5].data());
  Solve(&problem);
  return x;
}

// Marginalizes x0, x1 at the linearization point `x` and solves x2..x5.
std::vector<std::array<double, 3>> SolveReduced(const Chain& chain,
                                                std::vector<std::array<double, 3>> x) {
  const PosePriorFactor prior0(chain.truth[0], chain.prior_sqrt);
  const RelativePoseFactor odom01(chain.odometry[0], chain.odom_sqrt);
  const RelativePoseFactor odom12(chain.odometry[1], chain.odom_sqrt);
  const std::vector<LinearizationVariable> variables = {
      {x[0].data(), 3, true}, {x[1].data(), 3, true}, {x[2].data(), 3, true}};
  const std::vector<LinearizationFactor> factors = {
      {&prior0, nullptr, {0}}, {&odom01, nullptr, {0, 1}}, {&odom12, nullptr, {1, 2}}};
  const LinearSystem system = LinearizeFactors(variables, factors).value();
  const std::vector<int> keep = {6, 7, 8};
  const std::vector<int> marginalize = {0, 1, 2, 3, 4, 5};
  MarginalPrior prior;
  prior.x0 = {std::vector<double>(x[2].begin(), x[2].end())};
  prior.is_pose = {true};
  prior.sqrt_prior =
      SqrtPriorFromSystem(MarginalizeSchur(system, keep, marginalize).value()).value();

  ceres::Problem problem;
  for (int i = 2; i < 6; ++i) problem.AddParameterBlock(x[i].data(), 3, new core::SE2Manifold);
  x[3][0] += 0.2;  // start the reduced solve away from the answer
  x[4][2] -= 0.1;
  problem.AddResidualBlock(new MarginalPriorFactor(prior), nullptr, x[2].data());
  for (int i = 2; i < 5; ++i) {
    problem.AddResidualBlock(new RelativePoseFactor(chain.odometry[i], chain.odom_sqrt), nullptr,
                             x[i].data(), x[i + 1].data());
  }
  problem.AddResidualBlock(new PosePriorFactor(chain.fixes[0], chain.fix_sqrt), nullptr,
                           x[2].data());
  problem.AddResidualBlock(new PosePriorFactor(chain.fixes[1], chain.fix_sqrt), nullptr,
                           x[5].data());
  Solve(&problem);
  return x;
}

TEST(MarginalPrior, SchurAtTheOptimumReproducesTheBatchSolution) {
  for (std::uint32_t seed : {41u, 42u, 43u}) {
    const Chain chain(seed);
    const auto full = SolveFull(chain);
    const auto reduced = SolveReduced(chain, full);
    for (int i = 2; i < 6; ++i) {
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(reduced[i][k], full[i][k], 1e-7) << i << " " << k;
    }
  }
}

// Linearized at the dead-reckoned estimate (several cm and degrees from the
// optimum) the reduced solution is still within a few millimetres.
TEST(MarginalPrior, SchurAwayFromTheOptimumIsCloseToTheBatchSolution) {
  for (std::uint32_t seed : {44u, 45u, 46u}) {
    const Chain chain(seed);
    const auto full = SolveFull(chain);
    const auto reduced = SolveReduced(chain, chain.Initial());
    for (int i = 2; i < 6; ++i) {
      EXPECT_LT(std::hypot(reduced[i][0] - full[i][0], reduced[i][1] - full[i][1]), 5e-3) << i;
      EXPECT_LT(std::abs(core::WrapAngle(reduced[i][2] - full[i][2])), 2e-3) << i;
    }
  }
}

TEST(MarginalPriorFactor, JacobiansMatchNumeric) {
  std::mt19937 rng(47);
  std::normal_distribution<double> normal(0.0, 1.0);
  MarginalPrior prior;
  prior.x0 = {{1.0, 2.0, 3.0}, {0.5, -0.2}};
  prior.is_pose = {true, false};
  prior.sqrt_prior.J = Eigen::MatrixXd(5, 5);
  prior.sqrt_prior.r = Eigen::VectorXd(5);
  for (int i = 0; i < 25; ++i) prior.sqrt_prior.J(i) = normal(rng);
  for (int i = 0; i < 5; ++i) prior.sqrt_prior.r(i) = normal(rng);
  const MarginalPriorFactor factor(prior);
  const SE2 T(1.2, 1.7, -3.0);  // across the +-pi wrap from x0's yaw
  const Eigen::Vector2d line(0.6, -0.1);
  auto residual = [&](const SE2& pose, const Eigen::Vector2d& other) {
    const double p[3] = {pose.x(), pose.y(), pose.yaw()};
    const double* parameters[2] = {p, other.data()};
    Eigen::Matrix<double, 5, 1> r;
    factor.Evaluate(parameters, r.data(), nullptr);
    return r;
  };
  const double p[3] = {T.x(), T.y(), T.yaw()};
  const double* parameters[2] = {p, line.data()};
  Eigen::Matrix<double, 5, 1> r;
  Eigen::Matrix<double, 5, 3, Eigen::RowMajor> J_pose_ambient;
  Eigen::Matrix<double, 5, 2, Eigen::RowMajor> J_line;
  double* jacobians[2] = {J_pose_ambient.data(), J_line.data()};
  ASSERT_TRUE(factor.Evaluate(parameters, r.data(), jacobians));
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> plus;
  core::SE2Manifold().PlusJacobian(p, plus.data());
  const Eigen::Matrix<double, 5, 3> J_pose = J_pose_ambient * plus;
  EXPECT_JACOBIAN_NEAR(
      J_pose, [&](const SE2& x) { return residual(x, line); }, T, 1e-6);
  const Eigen::Matrix<double, 5, 2> J_line_col_major = J_line;
  EXPECT_JACOBIAN_NEAR(
      J_line_col_major, [&](const Eigen::Vector2d& v) { return residual(T, v); }, line, 1e-6);
}

}  // namespace
}  // namespace groundline::localization
