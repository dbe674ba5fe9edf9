// Ground-line, junction and pose-prior factors: residuals at the truth,
// tangent Jacobians against numeric differentiation (including lines through
// the origin and either description of the map line), the ambient lift under
// SE2Manifold, and a Ceres solve that recovers a pose from lines.
#include "groundline/localization/floor_factors.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "groundline/core/random_draws.h"
#include "groundline/core/se2_manifold.h"
#include "jacobian_check.h"
#include "random_pose.h"

namespace groundline::localization {
namespace {

using core::SE2;
using perception::HesseLine;
using RowMajor23 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
using RowMajor33 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

using ::groundline::testing::RandomPose;

Eigen::Matrix2d RandomSqrtInformation2(std::mt19937& rng) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  Eigen::Matrix2d A;
  for (int i = 0; i < 4; ++i) A(i) = entry(rng);
  const Eigen::Matrix2d covariance = 1e-3 * (A * A.transpose() + Eigen::Matrix2d::Identity());
  return SqrtInformationFromCovariance2(covariance).value();
}

Eigen::Vector2d LineVector(const HesseLine& line) { return {line.rho_m, line.alpha_rad}; }
HesseLine LineFromVector(const Eigen::Vector2d& v) { return {v(0), v(1)}; }

TEST(GroundLineFactor, ZeroAtTheTruthInEitherDescription) {
  const SE2 T_map_base(3.0, -1.0, 0.6);
  const HesseLine line_map{2.0, 0.3};
  const HesseLine measured = perception::InverseTransformLine(T_map_base, line_map);
  const GroundLineFactor factor(measured, Eigen::Matrix2d::Identity() * 100.0);
  EXPECT_LT(factor.Residual(T_map_base, line_map).norm(), 1e-12);
  // The flipped and the 2 pi-shifted descriptions describe the same line.
  EXPECT_LT(factor.Residual(T_map_base, {-2.0, 0.3 + std::numbers::pi}).norm(), 1e-12);
  EXPECT_LT(factor.Residual(T_map_base, {2.0, 0.3 - 2.0 * std::numbers::pi}).norm(), 1e-12);
  // A 1 cm shift of the vehicle along the line's normal shows in rho only.
  const SE2 shifted(T_map_base.translation() + 0.01 * line_map.Normal(), T_map_base.yaw());
  const Eigen::Vector2d r = factor.Residual(shifted, line_map);
  EXPECT_NEAR(std::abs(r(0)), 1.0, 1e-9);
  EXPECT_NEAR(r(1), 0.0, 1e-9);
}

TEST(GroundLineFactor, TangentJacobiansMatchNumeric) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> rho(-3.0, 3.0);
  std::uniform_real_distribution<double> angle(-4.0, 4.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (int trial = 0; trial < 300; ++trial) {
    const SE2 T_map_base = RandomPose(rng);
    const HesseLine line_map{rho(rng), angle(rng)};
    HesseLine measured = perception::InverseTransformLine(T_map_base, line_map);
    measured.rho_m += noise(rng);
    measured.alpha_rad += noise(rng);
    // Every third trial: a map line through (near) the vehicle, rho_base ~ 0.
    const HesseLine line =
        trial % 3 == 0 ? perception::TransformLine(T_map_base, {0.003, angle(rng)}) : line_map;
    const GroundLineFactor factor(measured, RandomSqrtInformation2(rng));
    Eigen::Matrix<double, 2, 3> J_T;
    Eigen::Matrix2d J_line;
    factor.Residual(T_map_base, line, &J_T, &J_line);
    EXPECT_JACOBIAN_NEAR(
        J_T, [&](const SE2& T) { return factor.Residual(T, line); }, T_map_base, 1e-5);
    EXPECT_JACOBIAN_NEAR(
        J_line,
        [&](const Eigen::Vector2d& v) { return factor.Residual(T_map_base, LineFromVector(v)); },
        LineVector(line), 1e-5);
  }
}

TEST(JunctionFactor, TangentJacobiansMatchNumeric) {
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> xy(-5.0, 5.0);
  for (int trial = 0; trial < 200; ++trial) {
    const SE2 T_map_base = RandomPose(rng);
    const Eigen::Vector2d point = core::DrawVector<2>(xy, rng);
    const Eigen::Matrix2d sqrt_information = RandomSqrtInformation2(rng);
    const JunctionFactor factor(core::DrawVector<2>(xy, rng), sqrt_information);
    Eigen::Matrix<double, 2, 3> J_T;
    Eigen::Matrix2d J_point;
    factor.Residual(T_map_base, point, &J_T, &J_point);
    EXPECT_JACOBIAN_NEAR(
        J_T, [&](const SE2& T) { return factor.Residual(T, point); }, T_map_base, 1e-6);
    EXPECT_JACOBIAN_NEAR(
        J_point, [&](const Eigen::Vector2d& p) { return factor.Residual(T_map_base, p); }, point,
        1e-6);
  }
  const SE2 T(1.0, 2.0, 0.5);
  const Eigen::Vector2d p_base(1.5, -0.3);
  const JunctionFactor exact(p_base, Eigen::Matrix2d::Identity());
  EXPECT_LT(exact.Residual(T, T * p_base).norm(), 1e-12);
}

TEST(PosePriorFactor, TangentJacobianMatchesNumeric) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 100; ++trial) {
    const SE2 T = RandomPose(rng);
    const PosePriorFactor factor(RandomPose(rng), Eigen::Matrix3d::Identity() * 3.0);
    core::Matrix3 J;
    factor.Residual(T, &J);
    EXPECT_JACOBIAN_NEAR(
        J, [&](const SE2& x) { return factor.Residual(x); }, T, 1e-6);
  }
}

TEST(FloorFactors, AmbientJacobiansTimesPlusJacobianGiveTangentJacobians) {
  std::mt19937 rng(24);
  const core::SE2Manifold manifold;
  for (int trial = 0; trial < 50; ++trial) {
    const SE2 T = RandomPose(rng);
    double pose[3] = {T.x(), T.y(), T.yaw()};
    RowMajor33 plus;
    manifold.PlusJacobian(pose, plus.data());
    double line[2] = {1.2, 0.4 + trial * 0.1};
    const GroundLineFactor line_factor({0.5, -0.2}, RandomSqrtInformation2(rng));
    const JunctionFactor junction_factor({1.0, 0.3}, RandomSqrtInformation2(rng));
    for (const ceres::CostFunction* cost :
         {static_cast<const ceres::CostFunction*>(&line_factor),
          static_cast<const ceres::CostFunction*>(&junction_factor)}) {
      const double* parameters[2] = {pose, line};
      double residual[2];
      RowMajor23 J_amb;
      Eigen::Matrix<double, 2, 2, Eigen::RowMajor> J_other;
      double* jacobians[2] = {J_amb.data(), J_other.data()};
      ASSERT_TRUE(cost->Evaluate(parameters, residual, jacobians));
      Eigen::Matrix<double, 2, 3> J_T;
      if (cost == &line_factor) {
        line_factor.Residual(T, {line[0], line[1]}, &J_T);
      } else {
        junction_factor.Residual(T, {line[0], line[1]}, &J_T);
      }
      EXPECT_LT((J_amb * plus - J_T).cwiseAbs().maxCoeff(), 1e-12);
    }
    const PosePriorFactor prior(RandomPose(rng), Eigen::Matrix3d::Identity());
    const double* parameters[1] = {pose};
    double residual[3];
    RowMajor33 J_amb;
    double* jacobians[1] = {J_amb.data()};
    ASSERT_TRUE(prior.Evaluate(parameters, residual, jacobians));
    core::Matrix3 J_T;
    prior.Residual(T, &J_T);
    EXPECT_LT((J_amb * plus - J_T).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// Three map lines (two parallel, one across) and a junction pin the pose; a
// Ceres solve from 20 cm / 6 deg off recovers it, with a map line block held
// in the flipped description.
TEST(FloorFactors, CeresRecoversThePoseFromLinesAndAJunction) {
  const SE2 T_true(4.0, 2.0, 0.3);
  std::vector<std::array<double, 2>> lines = {
      {3.0, 0.0}, {-5.0, std::numbers::pi}, {2.5, std::numbers::pi / 2}};
  const Eigen::Vector2d junction_map(3.0, 2.5);
  double pose[3] = {4.15, 1.87, 0.2};
  ceres::Problem problem;
  problem.AddParameterBlock(pose, 3, new core::SE2Manifold);
  const Eigen::Matrix2d S = Eigen::Vector2d(1.0 / 0.01, 1.0 / 0.005).asDiagonal();
  for (auto& line : lines) {
    const HesseLine z = perception::InverseTransformLine(T_true, {line[0], line[1]});
    problem.AddResidualBlock(new GroundLineFactor(z, S), new ceres::SoftLOneLoss(1.0), pose,
                             line.data());
    problem.SetParameterBlockConstant(line.data());
  }
  double junction[2] = {junction_map.x(), junction_map.y()};
  problem.AddResidualBlock(new JunctionFactor(T_true.Inverse() * junction_map, S * 0.5),
                           new ceres::SoftLOneLoss(1.0), pose, junction);
  problem.SetParameterBlockConstant(junction);
  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  EXPECT_TRUE(SE2(pose[0], pose[1], pose[2]).IsApprox(T_true, 1e-6, 1e-6))
      << pose[0] << " " << pose[1] << " " << pose[2];
}

}  // namespace
}  // namespace groundline::localization
