// Invariant suite for core::SE2 over seeded random trials and the special
// angles of se2_test_points.h (near 0, at the series switch, near +-pi).
// The Jacobians are checked in se2_jacobian_test.cc.
#include "groundline/core/se2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

#include "groundline/core/random_draws.h"
#include "se2_test_points.h"

namespace groundline::core {
namespace {

using testing::kPi;
using testing::MaxAbsDiff;
using testing::PosePoints;
using testing::TangentPoints;

Matrix3 Hat(const Vector3& xi) {
  Matrix3 m = Matrix3::Zero();
  m(0, 1) = -xi.z();
  m(1, 0) = xi.z();
  m(0, 2) = xi.x();
  m(1, 2) = xi.y();
  return m;
}

TEST(SE2, ExpMatchesMatrixExponential) {
  for (const Vector3& xi : TangentPoints()) {
    EXPECT_LT(MaxAbsDiff(SE2::Exp(xi).Matrix(), Hat(xi).exp()), 1e-12) << xi.transpose();
  }
}

TEST(SE2, ExpOfLogIsIdentity) {
  for (const SE2& t : PosePoints()) {
    EXPECT_TRUE(SE2::Exp(t.Log()).IsApprox(t, 1e-12, 1e-14)) << t.Vector().transpose();
  }
}

TEST(SE2, LogOfExpIsIdentityInsidePrincipalRange) {
  for (const Vector3& xi : TangentPoints()) {
    ASSERT_LT(std::abs(xi.z()), kPi);
    EXPECT_LT(MaxAbsDiff(SE2::Exp(xi).Log(), xi), 1e-12) << xi.transpose();
  }
}

TEST(SE2, ExpIsContinuousAcrossTheSeriesSwitch) {
  // Both sides of the 1e-4 switch must agree to the change in the argument.
  const Vector3 below(3.0, -2.0, 1e-4 * (1.0 - 1e-9));
  const Vector3 above(3.0, -2.0, 1e-4 * (1.0 + 1e-9));
  EXPECT_LT(MaxAbsDiff(SE2::Exp(below).Matrix(), SE2::Exp(above).Matrix()), 1e-12);
  EXPECT_LT(MaxAbsDiff(SE2::RightJacobian(below), SE2::RightJacobian(above)), 1e-11);
  EXPECT_LT(MaxAbsDiff(SE2::Exp(below).Log(), SE2::Exp(above).Log()), 1e-12);
}

TEST(SE2, LogReturnsWrappedAngleAtPi) {
  const SE2 t(1.0, 2.0, kPi);
  const Vector3 xi = t.Log();
  EXPECT_NEAR(std::abs(xi.z()), kPi, 1e-15);
  EXPECT_TRUE(SE2::Exp(xi).IsApprox(t, 1e-12, 1e-12));
}

TEST(SE2, PlusMinusInvariants) {
  const std::vector<SE2> poses = PosePoints();
  const std::vector<Vector3> deltas = TangentPoints(testing::kSeedOther);
  for (size_t i = 0; i < poses.size(); ++i) {
    const SE2& x = poses[i];
    const Vector3& d = deltas[i % deltas.size()];
    EXPECT_TRUE(x.Plus(Vector3::Zero()).IsApprox(x, 0.0, 0.0));
    EXPECT_LT(x.Minus(x).norm(), 1e-15);
    EXPECT_LT(MaxAbsDiff(x.Plus(d).Minus(x), d), 1e-11) << d.transpose();
    const SE2& y = poses[(i * 7 + 3) % poses.size()];
    EXPECT_TRUE(x.Plus(y.Minus(x)).IsApprox(y, 1e-11, 1e-12));
  }
}

TEST(SE2, GroupAxioms) {
  const std::vector<SE2> poses = PosePoints();
  const size_t n = poses.size();
  for (size_t i = 0; i < n; ++i) {
    const SE2& a = poses[i];
    const SE2& b = poses[(i * 7 + 1) % n];
    const SE2& c = poses[(i * 13 + 2) % n];
    EXPECT_TRUE(((a * b) * c).IsApprox(a * (b * c), 1e-12, 1e-12));
    EXPECT_TRUE((a * a.Inverse()).IsApprox(SE2::Identity(), 1e-12, 1e-15));
    EXPECT_TRUE((a.Inverse() * a).IsApprox(SE2::Identity(), 1e-12, 1e-15));
    EXPECT_TRUE(a.Inverse().Inverse().IsApprox(a, 1e-12, 0.0));
    EXPECT_TRUE((a * b).Inverse().IsApprox(b.Inverse() * a.Inverse(), 1e-12, 1e-15));
    EXPECT_TRUE(a.Between(b).IsApprox(a.Inverse() * b, 0.0, 0.0));
    EXPECT_TRUE((a * SE2::Identity()).IsApprox(a, 0.0, 0.0));
    EXPECT_LT(MaxAbsDiff((a * b).Matrix(), a.Matrix() * b.Matrix()), 1e-12);
    EXPECT_LT(MaxAbsDiff(a.Inverse().Matrix(), a.Matrix().inverse()), 1e-12);
  }
}

TEST(SE2, ActMatchesHomogeneousMatrix) {
  std::mt19937_64 rng(testing::kSeed);
  std::uniform_real_distribution<double> coord(-10.0, 10.0);
  for (const SE2& t : PosePoints()) {
    const Vector2 p = DrawVector<2>(coord, rng);
    const Vector3 expected = t.Matrix() * Vector3(p.x(), p.y(), 1.0);
    EXPECT_LT(MaxAbsDiff(t.Act(p), expected.head<2>()), 1e-12);
    EXPECT_EQ(MaxAbsDiff(t * p, t.Act(p)), 0.0);
    EXPECT_EQ(MaxAbsDiff(t.Rotation(), t.Matrix().topLeftCorner<2, 2>()), 0.0);
  }
}

TEST(SE2, AdjointConjugatesExp) {
  const std::vector<SE2> poses = PosePoints();
  const std::vector<Vector3> xis = TangentPoints(testing::kSeedOther);
  for (size_t i = 0; i < poses.size(); ++i) {
    const SE2& t = poses[i];
    const Vector3& xi = xis[i % xis.size()];
    EXPECT_TRUE(SE2::Exp(t.Adjoint() * xi).IsApprox(t * SE2::Exp(xi) * t.Inverse(), 1e-11, 1e-12));
  }
}

TEST(SE2, LeftAndRightJacobiansAgree) {
  for (const Vector3& xi : TangentPoints()) {
    const Matrix3 jr = SE2::RightJacobian(xi);
    const Matrix3 jl = SE2::LeftJacobian(xi);
    EXPECT_LT(MaxAbsDiff(jl, SE2::Exp(xi).Adjoint() * jr), 1e-12) << xi.transpose();
    EXPECT_LT(MaxAbsDiff(jr, SE2::LeftJacobian(-xi)), 1e-15) << xi.transpose();
    EXPECT_LT(MaxAbsDiff(jr * SE2::RightJacobianInverse(xi), Matrix3::Identity()), 1e-12);
    EXPECT_LT(MaxAbsDiff(SE2::RightJacobianInverse(xi) * jr, Matrix3::Identity()), 1e-12);
    EXPECT_LT(MaxAbsDiff(jl * SE2::LeftJacobianInverse(xi), Matrix3::Identity()), 1e-12);
  }
}

TEST(SE2, JacobiansAtZeroAreIdentity) {
  EXPECT_EQ(MaxAbsDiff(SE2::RightJacobian(Vector3::Zero()), Matrix3::Identity()), 0.0);
  EXPECT_EQ(MaxAbsDiff(SE2::LeftJacobianInverse(Vector3::Zero()), Matrix3::Identity()), 0.0);
}

TEST(SE2, ConstructorWrapsYaw) {
  EXPECT_NEAR(SE2(0.0, 0.0, 3.0 * kPi / 2.0).yaw(), -kPi / 2.0, 1e-15);
  EXPECT_NEAR(SE2(Vector2(1.0, 2.0), -5.0).yaw(), -5.0 + 2.0 * kPi, 1e-15);
  EXPECT_DOUBLE_EQ(SE2(1.0, 2.0, 0.3).Vector().x(), 1.0);
  EXPECT_DOUBLE_EQ(SE2(1.0, 2.0, 0.3).Vector().z(), 0.3);
}

TEST(SE2, IsApproxComparesWrappedAngles) {
  EXPECT_TRUE(SE2(0.0, 0.0, kPi).IsApprox(SE2(0.0, 0.0, -kPi), 0.0, 1e-15));
  EXPECT_FALSE(SE2(0.0, 0.0, 0.1).IsApprox(SE2(0.0, 0.0, 0.1 + 2e-9)));
  EXPECT_FALSE(SE2(0.0, 0.0, 0.1).IsApprox(SE2(2e-9, 0.0, 0.1)));
}

TEST(WrapAngle, KnownValues) {
  EXPECT_EQ(WrapAngle(0.0), 0.0);
  EXPECT_EQ(WrapAngle(1e-20), 1e-20);
  EXPECT_NEAR(std::abs(WrapAngle(kPi)), kPi, 1e-15);
  EXPECT_NEAR(std::abs(WrapAngle(-kPi)), kPi, 1e-15);
  EXPECT_NEAR(std::abs(WrapAngle(3.0 * kPi)), kPi, 1e-14);
  EXPECT_NEAR(WrapAngle(2.0 * kPi), 0.0, 1e-15);
  EXPECT_NEAR(WrapAngle(-2.0 * kPi), 0.0, 1e-15);
  EXPECT_NEAR(WrapAngle(7.0), 7.0 - 2.0 * kPi, 1e-15);
  EXPECT_NEAR(WrapAngle(-7.0), -7.0 + 2.0 * kPi, 1e-15);
  EXPECT_NEAR(WrapAngle(kPi + 0.1), -kPi + 0.1, 1e-15);
  EXPECT_NEAR(WrapAngle(-kPi - 0.1), kPi - 0.1, 1e-15);
}

TEST(WrapAngle, RandomAnglesLandInRangeWithSameDirection) {
  std::mt19937_64 rng(testing::kSeed);
  std::uniform_real_distribution<double> angle(-1000.0, 1000.0);
  for (int i = 0; i < testing::kRandomTrials; ++i) {
    const double a = angle(rng);
    const double w = WrapAngle(a);
    EXPECT_LE(std::abs(w), kPi);
    EXPECT_NEAR(std::cos(w), std::cos(a), 1e-12);
    EXPECT_NEAR(std::sin(w), std::sin(a), 1e-12);
  }
}

}  // namespace
}  // namespace groundline::core
