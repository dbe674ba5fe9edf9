#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "groundline/core/random_draws.h"
#include "groundline/perception/hesse_line.h"
#include "test_units.h"

namespace groundline::perception {
namespace {

using ::groundline::testing::kPi;

// Points on `line` at along-line coordinates s (from the line's foot point).
std::vector<Eigen::Vector2d> PointsAt(const HesseLine& line, const std::vector<double>& s) {
  std::vector<Eigen::Vector2d> points;
  for (double si : s) points.push_back(line.rho_m * line.Normal() + si * line.Direction());
  return points;
}

std::vector<double> Linspace(double from, double to, int count) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i) out.push_back(from + (to - from) * i / (count - 1));
  return out;
}

TEST(FitLineTls, ExactPointsGiveTheLineAndZeroResidual) {
  for (const HesseLine& truth :
       {HesseLine{2.0, 0.7}, HesseLine{0.4, -2.9}, HesseLine{1.0, kPi}, HesseLine{3.0, kPi / 2}}) {
    const std::vector<Eigen::Vector2d> points = PointsAt(truth, Linspace(-1.0, 3.0, 25));
    std::vector<double> weights;
    for (size_t i = 0; i < points.size(); ++i) weights.push_back(1.0 + (i % 4));
    for (bool weighted : {false, true}) {
      const core::Result<LineFit> fit = FitLineTls(
          points, weighted ? std::span<const double>(weights) : std::span<const double>(), 0.01);
      ASSERT_TRUE(fit.ok()) << fit.message();
      EXPECT_TRUE(IsNormalized(fit->line));
      EXPECT_NEAR(fit->line.rho_m, truth.rho_m, 1e-12);
      EXPECT_NEAR(core::WrapAngle(fit->line.alpha_rad - truth.alpha_rad), 0.0, 1e-12);
      EXPECT_LT(fit->rms_residual_m, 1e-12);
    }
  }
}

TEST(FitLineTls, TwoPointsGiveTheLineThroughThem) {
  const std::vector<Eigen::Vector2d> points = {{1.0, 2.0}, {3.0, -1.0}};
  const core::Result<LineFit> fit = FitLineTls(points, {}, 0.01);
  ASSERT_TRUE(fit.ok());
  const HesseLine through = LineFromPoints(points[0], points[1]).value();
  EXPECT_LT(LineDifference(fit->line, through).norm(), 1e-12);
}

TEST(FitLineTls, CovarianceClosedForm) {
  // Unit weights, points at s = -1, 0, 1 around the foot point (s0 = 0):
  // var(alpha) = sigma^2 / 2, var(rho) = sigma^2 / 3, no correlation.
  const HesseLine line{2.0, 0.4};
  const core::Result<LineFit> fit = FitLineTls(PointsAt(line, {-1.0, 0.0, 1.0}), {}, 0.1);
  ASSERT_TRUE(fit.ok());
  EXPECT_NEAR(fit->covariance(0, 0), 0.01 / 3.0, 1e-15);
  EXPECT_NEAR(fit->covariance(1, 1), 0.01 / 2.0, 1e-15);
  EXPECT_NEAR(fit->covariance(0, 1), 0.0, 1e-15);
}

// Sample covariance of (rho, alpha) over noisy fits against the predicted one:
// each entry within 10% of sqrt(C_ii C_jj).
void CheckCovarianceByMonteCarlo(const HesseLine& truth, const std::vector<double>& s,
                                 const std::vector<double>& weights, double sigma_m,
                                 std::uint32_t seed) {
  const std::vector<Eigen::Vector2d> clean = PointsAt(truth, s);
  const core::Result<LineFit> predicted = FitLineTls(clean, weights, sigma_m);
  ASSERT_TRUE(predicted.ok());
  const Eigen::Matrix2d& C = predicted->covariance;

  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  constexpr int kTrials = 5000;
  std::vector<Eigen::Vector2d> errors;
  std::vector<Eigen::Vector2d> noisy(clean.size());
  for (int trial = 0; trial < kTrials; ++trial) {
    for (size_t i = 0; i < clean.size(); ++i) {
      const double sigma_i = sigma_m / std::sqrt(weights.empty() ? 1.0 : weights[i]);
      noisy[i] = clean[i] + sigma_i * core::DrawVector<2>(gauss, rng);
    }
    const core::Result<LineFit> fit = FitLineTls(noisy, weights, sigma_m);
    ASSERT_TRUE(fit.ok());
    errors.push_back(LineDifference(fit->line, truth));
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& e : errors) mean += e / kTrials;
  Eigen::Matrix2d sample = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& e : errors)
    sample += (e - mean) * (e - mean).transpose() / (kTrials - 1);
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      EXPECT_NEAR(sample(i, j), C(i, j), 0.1 * std::sqrt(C(i, i) * C(j, j)))
          << "entry (" << i << ", " << j << ")\nsample:\n"
          << sample << "\npredicted:\n"
          << C;
    }
  }
  // The estimate is unbiased to first order.
  EXPECT_LT(std::abs(mean.x()), 4.0 * std::sqrt(C(0, 0) / kTrials));
  EXPECT_LT(std::abs(mean.y()), 4.0 * std::sqrt(C(1, 1) / kTrials));
}

TEST(FitLineTls, CovarianceMatchesMonteCarloUnweighted) {
  // A segment 0.5..2.5 m along the line from its foot point: strong rho-alpha correlation.
  CheckCovarianceByMonteCarlo({1.5, 0.4}, Linspace(0.5, 2.5, 30), {}, 0.01, 1234);
}

TEST(FitLineTls, CovarianceMatchesMonteCarloWeighted) {
  std::vector<double> weights;
  for (int i = 0; i < 40; ++i) weights.push_back(0.5 + 0.1 * (i % 7));
  CheckCovarianceByMonteCarlo({2.2, -2.5}, Linspace(-2.0, 0.5, 40), weights, 0.02, 99);
}

TEST(FitLineTls, RejectsDegenerateInput) {
  const std::vector<Eigen::Vector2d> one = {{1.0, 1.0}};
  EXPECT_NE(FitLineTls(one, {}, 0.01).message().find("at least 2 points"), std::string::npos);
  const std::vector<Eigen::Vector2d> same = {{1.0, 1.0}, {1.0, 1.0}, {1.0, 1.0}};
  EXPECT_NE(FitLineTls(same, {}, 0.01).message().find("coincide"), std::string::npos);
  const std::vector<Eigen::Vector2d> points = {{0.0, 0.0}, {1.0, 0.0}, {2.0, 0.1}};
  const std::vector<double> bad_weights = {1.0, 0.0, 1.0};
  EXPECT_NE(FitLineTls(points, bad_weights, 0.01).message().find("weight 1"), std::string::npos);
  const std::vector<double> short_weights = {1.0};
  EXPECT_FALSE(FitLineTls(points, short_weights, 0.01).ok());
  EXPECT_FALSE(FitLineTls(points, {}, 0.0).ok());
  const std::vector<Eigen::Vector2d> with_nan = {{0.0, 0.0}, {std::nan(""), 0.0}};
  EXPECT_NE(FitLineTls(with_nan, {}, 0.01).message().find("point 1"), std::string::npos);
}

}  // namespace
}  // namespace groundline::perception
