// SE2Manifold: Ceres' own manifold invariants, our numeric checks of the
// analytic Plus/Minus Jacobians (including at yaw = +-pi), agreement with
// core::SE2, and a small end-to-end pose alignment solved by Ceres.
#include "groundline/core/se2_manifold.h"

#include <ceres/ceres.h>
#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "groundline/core/random_draws.h"
#include "groundline/core/se2.h"
#include "jacobian_check.h"
#include "se2_test_points.h"

namespace groundline::core {
namespace {

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using testing::kPi;
using testing::NearWrap;
using testing::PosePoints;
using testing::TangentPoints;

// Runs Ceres' invariant suite (Plus(x,0)=x, Minus(x,x)=0, Minus(Plus(x,d),x)=d,
// Plus(x,Minus(y,x))=y, Plus/Minus Jacobians by Ridders differentiation,
// MinusJacobian*PlusJacobian=I, RightMultiplyByPlusJacobian).
void ExpectCeresInvariants(const ceres::Manifold& manifold, const ceres::Vector& x,
                           const ceres::Vector& delta, const ceres::Vector& y) {
  using namespace ceres;  // NOLINT: the macro names its matchers and Vector unqualified
  constexpr double kTolerance = 1e-9;
  EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
}

TEST(SE2Manifold, CeresInvariantsHold) {
  const SE2Manifold manifold;
  const std::vector<SE2> xs = PosePoints();
  const std::vector<SE2> ys = PosePoints(testing::kSeedOther);
  const std::vector<Vector3> deltas = TangentPoints(testing::kSeedOther);
  int checked = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    const SE2& y = ys[(i * 3 + 1) % ys.size()];
    // Ceres differentiates the ambient yaw with steps up to 1e-4, which
    // would straddle the wrap; the wrap itself is checked below.
    if (NearWrap(xs[i].yaw(), 1e-3) || NearWrap(y.yaw(), 1e-3)) continue;
    // Ceres measures Plus(x, Minus(y, x)) - y relative to |y|: for y at the
    // origin (|y| ~ 1e-9) and x metres away that ratio is round-off, not error.
    if (y.Vector().norm() < 1e-3) continue;
    ExpectCeresInvariants(manifold, xs[i].Vector(), deltas[i % deltas.size()], y.Vector());
    ++checked;
  }
  EXPECT_GT(checked, testing::kRandomTrials);
}

TEST(SE2Manifold, AgreesWithSE2PlusAndMinus) {
  const SE2Manifold manifold;
  const std::vector<SE2> xs = PosePoints();
  const std::vector<Vector3> deltas = TangentPoints(testing::kSeedOther);
  for (size_t i = 0; i < xs.size(); ++i) {
    const Vector3 x = xs[i].Vector();
    const Vector3& d = deltas[i % deltas.size()];
    Vector3 out;
    ASSERT_TRUE(manifold.Plus(x.data(), d.data(), out.data()));
    EXPECT_LE(std::abs(out.z()), kPi);
    EXPECT_TRUE(SE2(out.x(), out.y(), out.z()).IsApprox(xs[i].Plus(d), 1e-12, 1e-12));
    const Vector3 y = xs[(i * 11 + 5) % xs.size()].Vector();
    Vector3 y_minus_x;
    ASSERT_TRUE(manifold.Minus(y.data(), x.data(), y_minus_x.data()));
    EXPECT_LT((y_minus_x - SE2(y.x(), y.y(), y.z()).Minus(xs[i])).norm(), 1e-12);
  }
}

TEST(SE2Manifold, JacobiansMatchNumericIncludingAtTheWrap) {
  const SE2Manifold manifold;
  std::vector<SE2> xs = PosePoints();
  xs.push_back(SE2(1.0, 2.0, kPi));
  xs.push_back(SE2(1.0, 2.0, -kPi));
  for (const SE2& pose : xs) {
    const Vector3 x = pose.Vector();
    RowMajor3 plus_jacobian, minus_jacobian;
    ASSERT_TRUE(manifold.PlusJacobian(x.data(), plus_jacobian.data()));
    ASSERT_TRUE(manifold.MinusJacobian(x.data(), minus_jacobian.data()));
    // Ambient output unwrapped next to x, so the difference quotient does not
    // see the 2 pi jump when yaw is at +-pi.
    const auto plus = [&](const Vector3& d) {
      Vector3 out;
      manifold.Plus(x.data(), d.data(), out.data());
      out.z() = x.z() + WrapAngle(out.z() - x.z());
      return out;
    };
    const auto minus = [&](const Vector3& y) {
      Vector3 out;
      manifold.Minus(y.data(), x.data(), out.data());
      return out;
    };
    const Vector3 zero = Vector3::Zero();
    EXPECT_JACOBIAN_NEAR(plus_jacobian, plus, zero, 1e-9);
    EXPECT_JACOBIAN_NEAR(minus_jacobian, minus, x, 1e-9);
    EXPECT_TRUE((minus_jacobian * plus_jacobian).isIdentity(1e-15));
  }
}

TEST(SE2Manifold, RightMultiplyByPlusJacobianMatchesProduct) {
  const SE2Manifold manifold;
  std::mt19937_64 rng(testing::kSeed);
  std::normal_distribution<double> normal;
  const Vector3 x(0.5, -1.0, 2.5);
  RowMajor3 plus_jacobian;
  ASSERT_TRUE(manifold.PlusJacobian(x.data(), plus_jacobian.data()));
  for (int rows = 0; rows <= 5; ++rows) {
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> ambient(rows, 3), tangent(rows, 3);
    for (int i = 0; i < ambient.size(); ++i) ambient.data()[i] = normal(rng);
    ASSERT_TRUE(
        manifold.RightMultiplyByPlusJacobian(x.data(), rows, ambient.data(), tangent.data()));
    if (rows > 0) {
      EXPECT_LT((tangent - ambient * plus_jacobian).cwiseAbs().maxCoeff(), 1e-15);
    }
  }
}

// Residual of one correspondence, whitened: (T_a_b * p_b - p_a) / sigma.
struct PointResidual {
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    using std::cos;
    using std::sin;
    const T c = cos(pose[2]);
    const T s = sin(pose[2]);
    residual[0] = (c * p_b.x() - s * p_b.y() + pose[0] - p_a.x()) / sigma_m;
    residual[1] = (s * p_b.x() + c * p_b.y() + pose[1] - p_a.y()) / sigma_m;
    return true;
  }
  Vector2 p_a;
  Vector2 p_b;
  double sigma_m;
};

TEST(SE2Manifold, CeresAlignsNoisyPointsAcrossTheWrap) {
  const SE2 T_a_b_true(2.0, -1.0, kPi - 0.02);
  constexpr double kSigmaM = 0.01;
  constexpr int kNumPoints = 50;
  std::mt19937_64 rng(testing::kSeed);
  std::uniform_real_distribution<double> coord(-5.0, 5.0);
  std::normal_distribution<double> noise(0.0, kSigmaM);
  std::vector<PointResidual> residuals;
  for (int i = 0; i < kNumPoints; ++i) {
    const Vector2 p_b = DrawVector<2>(coord, rng);
    const Vector2 p_a = T_a_b_true * p_b + core::DrawVector<2>(noise, rng);
    residuals.push_back({p_a, p_b, kSigmaM});
  }

  // Closed-form least squares (2D Procrustes) as the reference optimum.
  Vector2 mean_a = Vector2::Zero(), mean_b = Vector2::Zero();
  for (const PointResidual& r : residuals) {
    mean_a += r.p_a / kNumPoints;
    mean_b += r.p_b / kNumPoints;
  }
  double dot = 0.0, cross = 0.0;
  for (const PointResidual& r : residuals) {
    const Vector2 a = r.p_a - mean_a, b = r.p_b - mean_b;
    dot += b.dot(a);
    cross += b.x() * a.y() - b.y() * a.x();
  }
  const double yaw_ls = std::atan2(cross, dot);
  const SE2 T_ls(mean_a - SE2(0.0, 0.0, yaw_ls).Rotation() * mean_b, yaw_ls);

  // Start on the other side of the wrap, half a metre off.
  Vector3 pose(2.4, -0.6, -kPi + 0.3);
  ceres::Problem problem;
  for (const PointResidual& r : residuals) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PointResidual, 2, 3>(new PointResidual(r)), nullptr,
        pose.data());
  }
  problem.SetManifold(pose.data(), new SE2Manifold);
  ceres::Solver::Options options;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();

  const SE2 T_est(pose.x(), pose.y(), pose.z());
  EXPECT_TRUE(T_est.IsApprox(T_ls, 1e-9, 1e-10)) << pose.transpose();
  // Within 5 sigma of the truth: sigma_t ~ 0.01/sqrt(50) m, sigma_yaw ~ 5e-4 rad.
  EXPECT_TRUE(T_est.IsApprox(T_a_b_true, 7e-3, 2.5e-3)) << pose.transpose();

  // The tangent-space covariance Ceres reports is the right-perturbation
  // covariance (J^T J)^-1 with J the SE2::Act Jacobians of the whitened residuals.
  Matrix3 information = Matrix3::Zero();
  for (const PointResidual& r : residuals) {
    Matrix23 j;
    T_est.Act(r.p_b, &j);
    information += j.transpose() * j / (kSigmaM * kSigmaM);
  }
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(cov_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {{pose.data(), pose.data()}};
  ASSERT_TRUE(covariance.Compute(blocks, &problem));
  RowMajor3 cov_tangent;
  ASSERT_TRUE(
      covariance.GetCovarianceBlockInTangentSpace(pose.data(), pose.data(), cov_tangent.data()));
  const Matrix3 expected = information.inverse();
  EXPECT_LT((cov_tangent - expected).cwiseAbs().maxCoeff(), 1e-6 * expected.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace groundline::core
