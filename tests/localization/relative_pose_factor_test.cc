// RelativePoseFactor: residual, tangent Jacobians against numeric
// differentiation, the ambient "lift" under SE2Manifold, square roots of
// (rank-deficient) information, and a Ceres solve in which a degenerate scan
// match constrains only the directions it measures.
#include "groundline/localization/relative_pose_factor.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <random>

#include "groundline/core/se2_manifold.h"
#include "jacobian_check.h"
#include "random_pose.h"

namespace groundline::localization {
namespace {

using core::Matrix3;
using core::SE2;
using core::Vector3;

using ::groundline::testing::RandomPose;

Matrix3 RandomSqrtInformation3(std::mt19937& rng) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  Matrix3 A;
  for (int i = 0; i < 9; ++i) A(i) = entry(rng);
  const Matrix3 information = A * A.transpose() + Matrix3::Identity();
  return SqrtInformation(information).value();
}

TEST(RelativePoseFactor, ResidualIsZeroAtTheMeasurement) {
  const SE2 T_w_a(1.0, -2.0, 0.7);
  const SE2 T_a_b(0.3, 0.05, -0.1);
  const RelativePoseFactor factor(T_a_b, Matrix3::Identity() * 10.0);
  EXPECT_LT(factor.Residual(T_w_a, T_w_a * T_a_b).norm(), 1e-12);
  // A 1 cm lateral error in b's frame shows as 10 * 0.01 in y (S = 10 I).
  const Vector3 r = factor.Residual(T_w_a, T_w_a * T_a_b * SE2(0.0, 0.01, 0.0));
  EXPECT_NEAR(r.x(), 0.0, 1e-12);
  EXPECT_NEAR(r.y(), 0.1, 1e-12);
  EXPECT_NEAR(r.z(), 0.0, 1e-12);
}

TEST(RelativePoseFactor, TangentJacobiansMatchNumeric) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const SE2 T_w_a = RandomPose(rng);
    // Estimates near and far from the measurement, including |error yaw| near pi.
    const SE2 T_w_b = RandomPose(rng);
    const SE2 T_a_b =
        trial % 2 == 0 ? T_w_a.Between(T_w_b) * SE2(0.02, -0.01, 0.03) : RandomPose(rng);
    const RelativePoseFactor factor(T_a_b, RandomSqrtInformation3(rng));
    Matrix3 J_a;
    Matrix3 J_b;
    factor.Residual(T_w_a, T_w_b, &J_a, &J_b);
    EXPECT_JACOBIAN_NEAR(
        J_a, [&](const SE2& a) { return factor.Residual(a, T_w_b); }, T_w_a, 1e-6);
    EXPECT_JACOBIAN_NEAR(
        J_b, [&](const SE2& b) { return factor.Residual(T_w_a, b); }, T_w_b, 1e-6);
  }
}

TEST(RelativePoseFactor, AmbientJacobiansTimesPlusJacobianGiveTangentJacobians) {
  std::mt19937 rng(12);
  const core::SE2Manifold manifold;
  for (int trial = 0; trial < 50; ++trial) {
    const SE2 T_w_a = RandomPose(rng);
    const SE2 T_w_b = RandomPose(rng);
    const RelativePoseFactor factor(T_w_a.Between(T_w_b) * SE2(0.1, 0.0, 0.2),
                                    RandomSqrtInformation3(rng));
    double a[3] = {T_w_a.x(), T_w_a.y(), T_w_a.yaw()};
    double b[3] = {T_w_b.x(), T_w_b.y(), T_w_b.yaw()};
    const double* parameters[2] = {a, b};
    double residual[3];
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> J_amb_a;
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> J_amb_b;
    double* jacobians[2] = {J_amb_a.data(), J_amb_b.data()};
    ASSERT_TRUE(factor.Evaluate(parameters, residual, jacobians));

    Matrix3 J_a;
    Matrix3 J_b;
    const Vector3 r = factor.Residual(T_w_a, T_w_b, &J_a, &J_b);
    EXPECT_LT((Eigen::Map<Vector3>(residual) - r).norm(), 1e-12);
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> plus_a;
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> plus_b;
    manifold.PlusJacobian(a, plus_a.data());
    manifold.PlusJacobian(b, plus_b.data());
    EXPECT_LT((J_amb_a * plus_a - J_a).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((J_amb_b * plus_b - J_b).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(SqrtInformation, SquaresBackToTheInformation) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 50; ++trial) {
    const Matrix3 S = RandomSqrtInformation3(rng);
    const Matrix3 information = S.transpose() * S;
    const Matrix3 S2 = SqrtInformation(information).value();
    EXPECT_LT((S2.transpose() * S2 - information).norm(), 1e-9 * information.norm());
  }
}

TEST(SqrtInformation, RankDeficientInformationKeepsOnlyTheConstrainedDirections) {
  // A corridor along x rotated by 30 deg: no information along the aisle.
  const double c = std::cos(0.5236);
  const double s = std::sin(0.5236);
  const Eigen::Vector3d along(c, s, 0.0);
  const Eigen::Vector3d across(-s, c, 0.0);
  const Matrix3 information =
      400.0 * across * across.transpose() +
      900.0 * Eigen::Vector3d::UnitZ() * Eigen::Vector3d::UnitZ().transpose();
  const Matrix3 S = SqrtInformation(information).value();
  EXPECT_LT((S.transpose() * S - information).norm(), 1e-9);
  EXPECT_LT((S * along).norm(), 1e-9);  // a step along the aisle costs nothing
  EXPECT_NEAR((S * across).norm(), 20.0, 1e-9);
  Eigen::FullPivLU<Matrix3> lu(S);
  EXPECT_EQ(lu.rank(), 2);
}

TEST(SqrtInformation, RejectsMatricesThatAreNotInformation) {
  Matrix3 not_psd = Matrix3::Identity();
  not_psd(2, 2) = -1.0;
  EXPECT_FALSE(SqrtInformation(not_psd).ok());
  Matrix3 not_symmetric = Matrix3::Identity();
  not_symmetric(0, 1) = 0.5;
  EXPECT_FALSE(SqrtInformation(not_symmetric).ok());
  Matrix3 not_finite = Matrix3::Identity();
  not_finite(1, 1) = std::nan("");
  EXPECT_FALSE(SqrtInformation(not_finite).ok());
  EXPECT_FALSE(SqrtInformationFromCovariance(Matrix3::Zero()).ok());
}

TEST(SqrtInformation, FromCovarianceInvertsTheCovariance) {
  Matrix3 covariance;
  covariance << 0.04, 0.01, 0.0, 0.01, 0.09, 0.002, 0.0, 0.002, 0.01;
  const Matrix3 S = SqrtInformationFromCovariance(covariance).value();
  EXPECT_LT((S.transpose() * S * covariance - Matrix3::Identity()).norm(), 1e-9);
}

// Odometry says b is 1.00 m ahead of a; a scan match in a corridor along x
// says 1.30 m ahead but carries information only across the aisle and in yaw,
// where it says y = 0.02 m, yaw = 0. The solution keeps the odometry's
// along-aisle distance and fuses the rest by their information. (With a
// non-zero measured yaw the 0.3 m along-aisle disagreement would leak
// yaw * 0.3 m into the lateral residual: the error lives in the measurement's
// frame, as it should.)
TEST(RelativePoseFactor, DegenerateScanMatchDoesNotPullAlongTheAisle) {
  const double odom_sigma_xy = 0.05;
  const double odom_sigma_yaw = 0.02;
  const Matrix3 odom_sqrt_info =
      Eigen::Vector3d(1.0 / odom_sigma_xy, 1.0 / odom_sigma_xy, 1.0 / odom_sigma_yaw).asDiagonal();
  Matrix3 scan_information = Matrix3::Zero();
  scan_information(1, 1) = 1.0 / (0.01 * 0.01);
  scan_information(2, 2) = 1.0 / (0.005 * 0.005);
  const Matrix3 scan_sqrt_info = SqrtInformation(scan_information).value();

  double a[3] = {0.0, 0.0, 0.0};
  double b[3] = {0.5, 0.3, -0.2};  // a poor initial guess
  ceres::Problem problem;
  problem.AddParameterBlock(a, 3, new core::SE2Manifold);
  problem.AddParameterBlock(b, 3, new core::SE2Manifold);
  problem.SetParameterBlockConstant(a);
  problem.AddResidualBlock(new RelativePoseFactor(SE2(1.0, 0.0, 0.0), odom_sqrt_info), nullptr, a,
                           b);
  problem.AddResidualBlock(new RelativePoseFactor(SE2(1.3, 0.02, 0.0), scan_sqrt_info), nullptr, a,
                           b);
  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();

  // Information-weighted fusion across the aisle; both say yaw = 0.
  const double w_odom_y = 1.0 / (odom_sigma_xy * odom_sigma_xy);
  const double w_scan_y = scan_information(1, 1);
  EXPECT_NEAR(b[2], 0.0, 1e-4);  // second-order SE(2) coupling only
  EXPECT_NEAR(b[1], w_scan_y * 0.02 / (w_odom_y + w_scan_y), 2e-4);
  // Along the aisle only the odometry speaks: 1.0 m, not pulled toward 1.3 m.
  EXPECT_NEAR(b[0], 1.0, 2e-3);
}

}  // namespace
}  // namespace groundline::localization
