#include "groundline/perception/hesse_line.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "groundline/core/random_draws.h"
#include "hesse_line_traits.h"
#include "jacobian_check.h"
#include "test_units.h"

namespace groundline::perception {
namespace {

using ::groundline::testing::kPi;

// The same line: zero difference in either description.
void ExpectSameLine(const HesseLine& a, const HesseLine& b, double tol) {
  const Eigen::Vector2d r = LineDifference(a, b);
  EXPECT_LT(r.cwiseAbs().maxCoeff(), tol)
      << "(" << a.rho_m << ", " << a.alpha_rad << ") vs (" << b.rho_m << ", " << b.alpha_rad << ")";
}

// Two points on the line, `spread` apart around its foot point shifted by `offset`.
std::pair<Eigen::Vector2d, Eigen::Vector2d> PointsOn(const HesseLine& line, double offset = 0.3,
                                                     double spread = 2.0) {
  const Eigen::Vector2d foot = line.rho_m * line.Normal() + offset * line.Direction();
  return {foot - 0.5 * spread * line.Direction(), foot + 0.5 * spread * line.Direction()};
}

std::vector<HesseLine> SampleLines() {
  return {{2.0, 0.3}, {0.5, -2.8}, {3.0, kPi}, {1.0, kPi / 2}, {1e-7, 1.2}, {0.8, -kPi / 2 + 1e-3}};
}

TEST(HesseLine, NormalizationKeepsTheLineAndItsInvariants) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> rho(-5.0, 5.0);
  std::uniform_real_distribution<double> alpha(-10.0, 10.0);
  for (int trial = 0; trial < 5000; ++trial) {
    const HesseLine raw{rho(rng), alpha(rng)};
    const HesseLine line = NormalizeLine(raw.rho_m, raw.alpha_rad);
    ASSERT_TRUE(IsNormalized(line)) << line.rho_m << " " << line.alpha_rad;
    EXPECT_GE(line.rho_m, 0.0);
    EXPECT_EQ(line.rho_m, std::abs(raw.rho_m));
    const auto [p, q] = PointsOn(raw);
    EXPECT_NEAR(SignedDistance(line, p), 0.0, 1e-12);
    EXPECT_NEAR(SignedDistance(line, q), 0.0, 1e-12);
  }
}

TEST(HesseLine, NormalizationEdgeCases) {
  EXPECT_EQ(NormalizeLine(1.0, -kPi).alpha_rad, kPi);  // alpha in (-pi, pi]
  EXPECT_EQ(NormalizeLine(1.0, kPi).alpha_rad, kPi);
  const HesseLine flipped = NormalizeLine(-1.0, 0.5);
  EXPECT_EQ(flipped.rho_m, 1.0);
  EXPECT_NEAR(flipped.alpha_rad, 0.5 - kPi, 1e-15);
  // Through the origin: alpha chosen in (-pi/2, pi/2], rho never -0.
  for (double alpha : {kPi, -kPi / 2, 2.0, -2.0, kPi / 2, 0.0}) {
    const HesseLine line = NormalizeLine(-0.0, alpha);
    EXPECT_TRUE(IsNormalized(line)) << alpha;
    EXPECT_FALSE(std::signbit(line.rho_m));
    EXPECT_GT(line.alpha_rad, -kPi / 2);
    EXPECT_LE(line.alpha_rad, kPi / 2);
  }
  EXPECT_NEAR(NormalizeLine(0.0, 2.0).alpha_rad, 2.0 - kPi, 1e-15);
  EXPECT_FALSE(IsNormalized({-1.0, 0.0}));
  EXPECT_FALSE(IsNormalized({0.0, kPi}));
  EXPECT_FALSE(IsNormalized({1.0, -kPi}));
}

TEST(HesseLine, FromPointsRecoversTheLine) {
  for (const HesseLine& truth : SampleLines()) {
    const HesseLine line_truth = NormalizeLine(truth.rho_m, truth.alpha_rad);
    const auto [p1, p2] = PointsOn(line_truth);
    const core::Result<HesseLine> line = LineFromPoints(p1, p2);
    ASSERT_TRUE(line.ok());
    EXPECT_TRUE(IsNormalized(*line));
    ExpectSameLine(*line, line_truth, 1e-12);
    const core::Result<HesseLine> reversed = LineFromPoints(p2, p1);
    ASSERT_TRUE(reversed.ok());
    EXPECT_NEAR(reversed->rho_m, line->rho_m, 1e-12);
    EXPECT_NEAR(core::WrapAngle(reversed->alpha_rad - line->alpha_rad), 0.0, 1e-12);
  }
  // The seed paper's convention: a line ahead of the vehicle crossing it.
  const core::Result<HesseLine> stop_bar = LineFromPoints({2.0, -1.0}, {2.0, 1.0});
  ASSERT_TRUE(stop_bar.ok());
  EXPECT_NEAR(stop_bar->rho_m, 2.0, 1e-15);
  EXPECT_NEAR(stop_bar->alpha_rad, 0.0, 1e-15);
}

TEST(HesseLine, FromPointsFailsForCoincidentPoints) {
  const core::Result<HesseLine> line = LineFromPoints({1.0, 2.0}, {1.0, 2.0});
  ASSERT_FALSE(line.ok());
  EXPECT_NE(line.message().find("coincide"), std::string::npos);
  EXPECT_FALSE(LineFromPoints({1.0, std::nan("")}, {1.0, 2.0}).ok());
}

TEST(HesseLine, FromPointsJacobiansMatchNumeric) {
  for (const HesseLine& truth : SampleLines()) {
    // Within a numeric step of rho = 0 the central difference straddles the
    // normalization flip and compares descriptions in different charts.
    if (std::abs(truth.rho_m) < 1e-3) continue;
    const auto points = PointsOn(NormalizeLine(truth.rho_m, truth.alpha_rad), -0.7, 1.5);
    const Eigen::Vector2d& p1 = points.first;  // lambdas capture these
    const Eigen::Vector2d& p2 = points.second;
    Eigen::Matrix2d J1, J2;
    ASSERT_TRUE(LineFromPoints(p1, p2, &J1, &J2).ok());
    EXPECT_JACOBIAN_NEAR(
        J1, [&](const Eigen::Vector2d& p) { return LineFromPoints(p, p2).value(); }, p1, 1e-7);
    EXPECT_JACOBIAN_NEAR(
        J2, [&](const Eigen::Vector2d& p) { return LineFromPoints(p1, p).value(); }, p2, 1e-7);
  }
}

TEST(HesseLine, SignedDistanceIsPositiveBeyondTheLineAndHasExactJacobians) {
  const HesseLine line{2.0, 0.0};  // x = 2
  EXPECT_DOUBLE_EQ(SignedDistance(line, {3.0, 5.0}), 1.0);
  EXPECT_DOUBLE_EQ(SignedDistance(line, {0.0, -1.0}), -2.0);
  for (const HesseLine& l : SampleLines()) {
    const Eigen::Vector2d point(0.7, -1.9);
    Eigen::RowVector2d J_line, J_point;
    SignedDistance(l, point, &J_line, &J_point);
    EXPECT_JACOBIAN_NEAR(
        J_line, [&](const HesseLine& x) { return SignedDistance(x, point); }, l, 1e-8);
    EXPECT_JACOBIAN_NEAR(
        J_point, [&](const Eigen::Vector2d& p) { return SignedDistance(l, p); }, point, 1e-8);
  }
}

TEST(HesseLine, TransformMovesTheLineWithItsPoints) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Vector3d t = core::DrawVector<3>(unit, rng);
    const core::SE2 T_a_b(3.0 * t(0), 3.0 * t(1), kPi * t(2));
    const Eigen::Vector2d l = core::DrawVector<2>(unit, rng);
    const HesseLine line_b = NormalizeLine(2.0 * l(0), kPi * l(1));
    const auto [p, q] = PointsOn(line_b);
    const HesseLine line_a = TransformLine(T_a_b, line_b);
    EXPECT_TRUE(IsNormalized(line_a));
    EXPECT_NEAR(SignedDistance(line_a, T_a_b * p), 0.0, 1e-12);
    EXPECT_NEAR(SignedDistance(line_a, T_a_b * q), 0.0, 1e-12);
    // Round trips, and the inverse equals the transform by the inverse pose.
    ExpectSameLine(InverseTransformLine(T_a_b, line_a), line_b, 1e-12);
    ExpectSameLine(TransformLine(T_a_b, InverseTransformLine(T_a_b, line_b)), line_b, 1e-12);
    ExpectSameLine(InverseTransformLine(T_a_b, line_b), TransformLine(T_a_b.Inverse(), line_b),
                   1e-12);
  }
}

TEST(HesseLine, MapLineSeenFromTheVehicle) {
  // A stop bar across the aisle at x = 10 m in map; the vehicle at x = 7 m
  // facing +x sees it 3 m ahead with its normal forward; turned around, behind.
  const HesseLine stop_bar_map{10.0, 0.0};
  const HesseLine ahead = InverseTransformLine(core::SE2(7.0, 1.0, 0.0), stop_bar_map);
  EXPECT_NEAR(ahead.rho_m, 3.0, 1e-12);
  EXPECT_NEAR(ahead.alpha_rad, 0.0, 1e-12);
  const HesseLine behind = InverseTransformLine(core::SE2(7.0, 1.0, kPi), stop_bar_map);
  EXPECT_NEAR(behind.rho_m, 3.0, 1e-12);
  EXPECT_NEAR(std::abs(behind.alpha_rad), kPi, 1e-12);
  // Vehicle past the bar: the prediction flips to keep rho >= 0.
  const HesseLine past = InverseTransformLine(core::SE2(12.0, 0.0, 0.0), stop_bar_map);
  EXPECT_NEAR(past.rho_m, 2.0, 1e-12);
  EXPECT_NEAR(past.alpha_rad, kPi, 1e-12);
}

TEST(HesseLine, TransformJacobiansMatchNumeric) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d t = core::DrawVector<3>(unit, rng);
    const core::SE2 T(3.0 * t(0), 3.0 * t(1), kPi * t(2));
    const Eigen::Vector2d l = core::DrawVector<2>(unit, rng);
    const HesseLine line = NormalizeLine(0.1 + 2.0 * std::abs(l(0)), kPi * l(1));
    Matrix23 J_T;
    Eigen::Matrix2d J_l;
    TransformLine(T, line, &J_T, &J_l);
    EXPECT_JACOBIAN_NEAR(
        J_T, [&](const core::SE2& x) { return TransformLine(x, line); }, T, 1e-7);
    EXPECT_JACOBIAN_NEAR(
        J_l, [&](const HesseLine& l) { return TransformLine(T, l); }, line, 1e-7);
    InverseTransformLine(T, line, &J_T, &J_l);
    EXPECT_JACOBIAN_NEAR(
        J_T, [&](const core::SE2& x) { return InverseTransformLine(x, line); }, T, 1e-7);
    EXPECT_JACOBIAN_NEAR(
        J_l, [&](const HesseLine& l) { return InverseTransformLine(T, l); }, line, 1e-7);
  }
}

TEST(HesseLine, DifferenceIsZeroForTheSameLineInEitherDescription) {
  for (const HesseLine& line : SampleLines()) {
    const HesseLine other{-line.rho_m, line.alpha_rad + kPi};
    EXPECT_LT(LineDifference(line, other).norm(), 1e-12);
    EXPECT_LT(LineDifference(other, line).norm(), 1e-12);
    EXPECT_LT(LineDifference(line, {line.rho_m, line.alpha_rad - 2 * kPi}).norm(), 1e-12);
  }
  const Eigen::Vector2d r = LineDifference({2.5, 0.1}, {2.0, -0.1});
  EXPECT_NEAR(r.x(), 0.5, 1e-15);
  EXPECT_NEAR(r.y(), 0.2, 1e-15);
  // Wrap-around: alphas on either side of +-pi.
  EXPECT_NEAR(LineDifference({1.0, kPi - 0.01}, {1.0, -kPi + 0.01}).y(), -0.02, 1e-12);
}

TEST(HesseLine, DifferenceIsContinuousThroughTheOrigin) {
  // Two parallel lines 2 um apart on either side of the origin: normalized, their
  // normals are opposite, yet the difference is the small true offset.
  const HesseLine a = NormalizeLine(1e-6, 0.3);
  const HesseLine b = NormalizeLine(-1e-6, 0.3);
  const Eigen::Vector2d r = LineDifference(a, b);
  EXPECT_NEAR(std::abs(r.x()), 2e-6, 1e-15);
  EXPECT_NEAR(r.y(), 0.0, 1e-15);
  // A line swept through the origin: the difference to a fixed line changes smoothly.
  const HesseLine fixed{0.0, 0.3};
  double previous = LineDifference(NormalizeLine(-1e-3, 0.3), fixed).x();
  for (double rho = -1e-3 + 1e-5; rho <= 1e-3; rho += 1e-5) {
    const double current = LineDifference(NormalizeLine(rho, 0.3), fixed).x();
    EXPECT_NEAR(current - previous, 1e-5, 1e-12) << rho;
    previous = current;
  }
}

// Estimates of a line 0.5 mm from the origin, drawn from a strongly correlated
// covariance (a 1 m line 2 m ahead): about half come out normalized the other
// way round from the truth. Their errors, taken in their own descriptions
// (LineError), weighed by their own covariances (NormalizeLine carries the
// covariance through the flip), must be chi-square with 2 degrees of freedom.
TEST(HesseLine, LineErrorIsWeighedByTheEstimatesOwnCovarianceThroughTheFlip) {
  const HesseLine truth = NormalizeLine(5e-4, kPi / 2);
  // sd rho 2 mm, sd alpha 1 mrad, correlation 0.95.
  Eigen::Matrix2d C;
  C << 4e-6, 0.95 * 2e-3 * 1e-3, 0.95 * 2e-3 * 1e-3, 1e-6;
  const Eigen::Matrix2d L = C.llt().matrixL();
  std::mt19937 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  constexpr int kTrials = 4000;
  int flipped = 0, inside = 0, inside_truth_description = 0;
  double mean_nees = 0.0;
  for (int t = 0; t < kTrials; ++t) {
    const Eigen::Vector2d d = L * core::DrawVector<2>(n01, rng);
    Eigen::Matrix2d covariance = C;
    const HesseLine estimate =
        NormalizeLine(truth.rho_m + d(0), truth.alpha_rad + d(1), &covariance);
    flipped += std::abs(core::WrapAngle(estimate.alpha_rad - truth.alpha_rad)) > kPi / 2;
    const Eigen::Vector2d e = LineError(estimate, truth);
    const double nees = e.dot(covariance.inverse() * e);
    mean_nees += nees / kTrials;
    inside += nees >= 0.0506 && nees <= 7.378;
    // The difference in the truth's description has the same magnitudes ..
    const Eigen::Vector2d r = LineDifference(estimate, truth);
    EXPECT_NEAR(std::abs(r(0)), std::abs(e(0)), 1e-15);
    EXPECT_NEAR(r(1), e(1), 1e-15);
    // .. and is what a covariance carried into that description weighs.
    const Eigen::Matrix2d in_truth = CovarianceInDescriptionOf(estimate, truth, covariance);
    const double nees_truth = r.dot(in_truth.inverse() * r);
    EXPECT_NEAR(nees_truth, nees, 1e-9 * (1.0 + nees));
    inside_truth_description += nees_truth >= 0.0506 && nees_truth <= 7.378;
  }
  EXPECT_GT(flipped, kTrials / 4);
  EXPECT_NEAR(mean_nees, 2.0, 0.15);
  EXPECT_NEAR(static_cast<double>(inside) / kTrials, 0.95, 0.015);
  EXPECT_EQ(inside_truth_description, inside);
}

TEST(HesseLine, NormalizeLineCarriesTheCovarianceThroughTheFlip) {
  Eigen::Matrix2d C;
  C << 4.0, 1.5, 1.5, 2.0;
  Eigen::Matrix2d kept = C;
  EXPECT_NEAR(NormalizeLine(0.3, 0.2, &kept).rho_m, 0.3, 1e-15);
  EXPECT_EQ(kept, C);
  Eigen::Matrix2d flipped = C;
  const HesseLine line = NormalizeLine(-0.3, 0.2, &flipped);
  EXPECT_NEAR(line.rho_m, 0.3, 1e-15);
  EXPECT_NEAR(line.alpha_rad, 0.2 + kPi - 2 * kPi, 1e-12);
  EXPECT_EQ(flipped(0, 0), 4.0);
  EXPECT_EQ(flipped(1, 1), 2.0);
  EXPECT_EQ(flipped(0, 1), -1.5);
  EXPECT_EQ(flipped(1, 0), -1.5);
  EXPECT_NEAR(NormalizeLine(-0.3, 0.2, nullptr).rho_m, 0.3, 1e-15);
}

TEST(HesseLine, DifferenceJacobiansMatchNumeric) {
  const std::vector<std::pair<HesseLine, HesseLine>> pairs = {{{2.0, 0.3}, {1.9, 0.35}},
                                                              {{1e-4, 0.3}, {1e-4, 0.3 + kPi}},
                                                              {{1.0, kPi - 0.01}, {1.1, -kPi}}};
  for (const auto& [a, b] : pairs) {
    Eigen::Matrix2d J_a, J_b;
    LineDifference(a, b, &J_a, &J_b);
    const HesseLine b_copy = b;
    const HesseLine a_copy = a;
    EXPECT_JACOBIAN_NEAR(
        J_a,
        [&](const Eigen::Vector2d& x) {
          return LineDifference({x(0), x(1)}, b_copy);
        },
        Eigen::Vector2d(a.rho_m, a.alpha_rad), 1e-8);
    EXPECT_JACOBIAN_NEAR(
        J_b,
        [&](const Eigen::Vector2d& x) {
          return LineDifference(a_copy, {x(0), x(1)});
        },
        Eigen::Vector2d(b.rho_m, b.alpha_rad), 1e-8);
  }
}

}  // namespace
}  // namespace groundline::perception
