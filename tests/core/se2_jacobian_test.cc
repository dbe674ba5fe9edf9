// Every analytic Jacobian of core::SE2 against central differences on the
// manifold (right perturbations), at seeded random points and at angles near
// 0, at the series switch and near +-pi (se2_test_points.h).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "groundline/core/random_draws.h"
#include "groundline/core/se2.h"
#include "jacobian_check.h"
#include "se2_test_points.h"

namespace groundline::core {
namespace {

using testing::NearWrap;
using testing::PosePoints;
using testing::TangentPoints;

// Central differences with a 1e-6 step on quantities of a few metres leave
// about 1e-9 of round-off; 1e-7 still catches any wrong term.
constexpr double kTol = 1e-7;

// Pairs (a, b) covering the special angles for both arguments.
struct PosePair {
  SE2 a;
  SE2 b;
};
std::vector<PosePair> PosePairs() {
  const std::vector<SE2> first = PosePoints();
  const std::vector<SE2> second = PosePoints(testing::kSeedOther);
  std::vector<PosePair> pairs;
  for (size_t i = 0; i < first.size(); ++i) {
    pairs.push_back({first[i], second[(i * 5 + 1) % second.size()]});
  }
  return pairs;
}

TEST(SE2Jacobian, Exp) {
  for (const Vector3& xi : TangentPoints()) {
    Matrix3 j;
    SE2::Exp(xi, &j);
    const auto f = [](const Vector3& v) { return SE2::Exp(v); };
    EXPECT_JACOBIAN_NEAR(j, f, xi, kTol) << xi.transpose();
  }
}

TEST(SE2Jacobian, Log) {
  int checked = 0;
  for (const SE2& t : PosePoints()) {
    if (NearWrap(t.yaw())) continue;  // Log jumps by 2 pi across the wrap
    Matrix3 j;
    t.Log(&j);
    const auto f = [](const SE2& v) { return v.Log(); };
    EXPECT_JACOBIAN_NEAR(j, f, t, kTol) << t.Vector().transpose();
    ++checked;
  }
  EXPECT_GT(checked, testing::kRandomTrials);
}

TEST(SE2Jacobian, ComposeBothArguments) {
  for (const PosePair& pair : PosePairs()) {
    const SE2& a = pair.a;  // not a structured binding: lambdas capture these
    const SE2& b = pair.b;
    Matrix3 j_a, j_b;
    a.Compose(b, &j_a, &j_b);
    const auto f_a = [&](const SE2& v) { return v.Compose(b); };
    const auto f_b = [&](const SE2& v) { return a.Compose(v); };
    EXPECT_JACOBIAN_NEAR(j_a, f_a, a, kTol);
    EXPECT_JACOBIAN_NEAR(j_b, f_b, b, kTol);
  }
}

TEST(SE2Jacobian, Inverse) {
  for (const SE2& t : PosePoints()) {
    Matrix3 j;
    t.Inverse(&j);
    const auto f = [](const SE2& v) { return v.Inverse(); };
    EXPECT_JACOBIAN_NEAR(j, f, t, kTol) << t.Vector().transpose();
  }
}

TEST(SE2Jacobian, BetweenBothArguments) {
  for (const PosePair& pair : PosePairs()) {
    const SE2& a = pair.a;  // not a structured binding: lambdas capture these
    const SE2& b = pair.b;
    Matrix3 j_a, j_b;
    a.Between(b, &j_a, &j_b);
    const auto f_a = [&](const SE2& v) { return v.Between(b); };
    const auto f_b = [&](const SE2& v) { return a.Between(v); };
    EXPECT_JACOBIAN_NEAR(j_a, f_a, a, kTol);
    EXPECT_JACOBIAN_NEAR(j_b, f_b, b, kTol);
  }
}

TEST(SE2Jacobian, ActBothArguments) {
  std::mt19937_64 rng(testing::kSeed);
  std::uniform_real_distribution<double> coord(-10.0, 10.0);
  for (const SE2& t : PosePoints()) {
    const Vector2 p = DrawVector<2>(coord, rng);
    Matrix23 j_t;
    Matrix2 j_p;
    t.Act(p, &j_t, &j_p);
    const auto f_t = [&](const SE2& v) { return v.Act(p); };
    const auto f_p = [&](const Vector2& v) { return t.Act(v); };
    EXPECT_JACOBIAN_NEAR(j_t, f_t, t, kTol);
    EXPECT_JACOBIAN_NEAR(j_p, f_p, p, kTol);
  }
}

TEST(SE2Jacobian, PlusBothArguments) {
  const std::vector<Vector3> deltas = TangentPoints(testing::kSeedOther);
  const std::vector<SE2> poses = PosePoints();
  for (size_t i = 0; i < poses.size(); ++i) {
    const SE2& x = poses[i];
    const Vector3& d = deltas[(i * 3 + 2) % deltas.size()];
    Matrix3 j_x, j_d;
    x.Plus(d, &j_x, &j_d);
    const auto f_x = [&](const SE2& v) { return v.Plus(d); };
    const auto f_d = [&](const Vector3& v) { return x.Plus(v); };
    EXPECT_JACOBIAN_NEAR(j_x, f_x, x, kTol);
    EXPECT_JACOBIAN_NEAR(j_d, f_d, d, kTol);
  }
}

TEST(SE2Jacobian, MinusBothArguments) {
  int checked = 0;
  for (const PosePair& pair : PosePairs()) {
    const SE2& a = pair.a;  // not a structured binding: lambdas capture these
    const SE2& b = pair.b;
    Matrix3 j_a, j_b;
    const Vector3 d = a.Minus(b, &j_a, &j_b);
    if (NearWrap(d.z())) continue;  // the result jumps by 2 pi across the wrap
    const auto f_a = [&](const SE2& v) { return v.Minus(b); };
    const auto f_b = [&](const SE2& v) { return a.Minus(v); };
    EXPECT_JACOBIAN_NEAR(j_a, f_a, a, kTol);
    EXPECT_JACOBIAN_NEAR(j_b, f_b, b, kTol);
    ++checked;
  }
  EXPECT_GT(checked, testing::kRandomTrials);
}

TEST(SE2Jacobian, MinusNearTheWrapAndNearIdentity) {
  // Relative angles right next to 0 and to +-pi (but clear of the 1e-6 step).
  for (double theta : testing::SpecialAngles()) {
    if (NearWrap(theta)) continue;
    const SE2 b(1.0, -2.0, 0.7);
    const SE2 a = b * SE2::Exp(Vector3(0.4, 0.3, theta));
    Matrix3 j_a, j_b;
    a.Minus(b, &j_a, &j_b);
    const auto f_a = [&](const SE2& v) { return v.Minus(b); };
    const auto f_b = [&](const SE2& v) { return a.Minus(v); };
    EXPECT_JACOBIAN_NEAR(j_a, f_a, a, kTol) << theta;
    EXPECT_JACOBIAN_NEAR(j_b, f_b, b, kTol) << theta;
  }
}

TEST(SE2Jacobian, NullJacobianPointersAreAccepted) {
  const SE2 a(1.0, 2.0, 0.3);
  const SE2 b(-1.0, 0.5, -2.0);
  Matrix3 j;
  EXPECT_TRUE(a.Compose(b, nullptr, &j).IsApprox(a * b, 0.0, 0.0));
  EXPECT_EQ(j, Matrix3::Identity());
  EXPECT_TRUE(a.Between(b, &j, nullptr).IsApprox(a.Inverse() * b, 0.0, 0.0));
  EXPECT_TRUE(j.isApprox(-(a.Between(b).Inverse().Adjoint())));
}

}  // namespace
}  // namespace groundline::core
