// The chain solver of the sliding-window smoother against the Ceres batch
// solution of the same window (SmootherSolver::kCeres, converged tightly):
// the same keyframes, odometry, floor lines (one an outlier under the robust
// loss), junctions and a rank-deficient relative measurement, with and
// without marginalization. Both smoothers see identical inputs; every window
// pose and the newest covariance must agree.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "groundline/localization/sliding_window_smoother.h"

namespace groundline::localization {
namespace {

constexpr double kTapeY = 0.6;  // aisle tapes at y = +-0.6 m, cross lines at x = 0, 1, 2, ...

Atlas AisleAtlas() {
  Atlas atlas;
  const auto add_line = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    AtlasLine line;
    line.id = static_cast<std::int64_t>(atlas.lines.size());
    const Eigen::Vector2d d = (b - a).normalized();
    const Eigen::Vector2d normal(-d.y(), d.x());
    line.line_map = perception::NormalizeLine(normal.dot(a), std::atan2(normal.y(), normal.x()));
    line.covariance = Eigen::Vector2d(1e-6, 1e-6).asDiagonal();
    line.endpoint_a_m = a;
    line.endpoint_b_m = b;
    atlas.lines.push_back(line);
  };
  add_line({-1.0, kTapeY}, {30.0, kTapeY});
  add_line({-1.0, -kTapeY}, {30.0, -kTapeY});
  for (int k = 0; k <= 30; ++k) {
    add_line({k, -kTapeY}, {k, kTapeY});
    AtlasJunction junction;
    junction.id = k;
    junction.point_m = {k, kTapeY};
    junction.covariance = Eigen::Matrix2d::Identity() * 1e-6;
    atlas.junctions.push_back(junction);
  }
  return atlas;
}

struct Step {
  double stamp_s = 0.0;
  RelativeMotion motion;
  FloorObservations observations;
  RelativePoseMeasurement relative;
};

// A weaving drive along the aisle: biased noisy odometry, the lines and
// junctions 0.6-2.4 m ahead with noise of their stated covariance, and every
// 7th keyframe the +y tape observed 3 sigma off (an outlier the loss bends).
std::vector<Step> AisleDrive(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const Atlas atlas = AisleAtlas();
  const auto truth = [](int i) {
    const double x = 0.2 * i;
    return core::SE2(x, 0.1 * std::sin(0.5 * x), 0.05 * std::cos(0.5 * x));
  };
  const Eigen::Vector3d odometry_sigma(0.01, 0.01, 0.003);
  const double line_sigma = 0.005;
  std::vector<Step> steps;
  for (int i = 1; i <= n; ++i) {
    const core::SE2 T = truth(i);
    Step step;
    step.stamp_s = 0.1 * i;
    const core::SE2 T_prev_curr = truth(i - 1).Inverse() * T;
    const Eigen::Vector3d noise(odometry_sigma.x() * normal(rng) + 0.005,
                                odometry_sigma.y() * normal(rng) + 0.003,
                                odometry_sigma.z() * normal(rng));
    step.motion.T_start_end = T_prev_curr * core::SE2::Exp(noise);
    step.motion.covariance = odometry_sigma.cwiseAbs2().asDiagonal();
    step.relative.T_prev_curr = T_prev_curr * core::SE2::Exp(Eigen::Vector3d(0.0, 0.0, 1e-3));
    step.relative.sqrt_information = Eigen::Vector3d(0.0, 200.0, 1000.0).asDiagonal();
    step.observations.stamp_s = step.stamp_s;
    for (size_t l = 0; l < atlas.lines.size(); ++l) {
      const AtlasLine& line = atlas.lines[l];
      const bool tape = l < 2;
      const double ahead = line.endpoint_a_m.x() - T.x();
      if (!tape && (ahead < 0.6 || ahead > 2.4)) continue;
      const Eigen::Vector2d a =
          tape ? Eigen::Vector2d(T.x() + 0.6, line.endpoint_a_m.y()) : line.endpoint_a_m;
      const Eigen::Vector2d b =
          tape ? Eigen::Vector2d(T.x() + 2.4, line.endpoint_a_m.y()) : line.endpoint_b_m;
      LineObservation observation;
      observation.line_base = perception::InverseTransformLine(T, line.line_map);
      observation.line_base.rho_m += line_sigma * normal(rng);
      observation.line_base.alpha_rad += line_sigma * normal(rng);
      if (l == 0 && i % 7 == 0) observation.line_base.rho_m += 3.0 * line_sigma;
      observation.covariance = Eigen::Matrix2d::Identity() * line_sigma * line_sigma;
      observation.endpoint_a_base_m = T.Inverse() * a;
      observation.endpoint_b_base_m = T.Inverse() * b;
      step.observations.lines.push_back(observation);
    }
    for (const AtlasJunction& junction : atlas.junctions) {
      const double ahead = junction.point_m.x() - T.x();
      if (ahead < 0.6 || ahead > 2.4) continue;
      JunctionObservation observation;
      observation.point_base_m =
          T.Inverse() * junction.point_m + 0.01 * Eigen::Vector2d(normal(rng), normal(rng));
      observation.covariance = Eigen::Matrix2d::Identity() * 1e-4;
      step.observations.junctions.push_back(observation);
    }
    steps.push_back(step);
  }
  return steps;
}

void ExpectChainEqualsCeres(double window_s, bool with_relative) {
  SmootherOptions chain_options;
  chain_options.window_s = window_s;
  chain_options.step_tolerance = 1e-10;
  chain_options.max_iterations = 50;
  SmootherOptions ceres_options = chain_options;
  ceres_options.solver = SmootherSolver::kCeres;
  ceres_options.ceres_tolerance = 1e-12;
  ceres_options.max_iterations = 200;
  SlidingWindowSmoother chain(chain_options, AisleAtlas());
  SlidingWindowSmoother ceres(ceres_options, AisleAtlas());
  const core::Matrix3 start_covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  chain.Initialize(0.0, core::SE2(0.0, 0.0, 0.05), start_covariance);
  ceres.Initialize(0.0, core::SE2(0.0, 0.0, 0.05), start_covariance);
  int robust_lines = 0;
  for (const Step& step : AisleDrive(30, 5)) {
    std::optional<RelativePoseMeasurement> relative;
    if (with_relative) relative = step.relative;
    const auto a = chain.AddKeyframe(step.stamp_s, step.motion, step.observations, relative);
    const auto b = ceres.AddKeyframe(step.stamp_s, step.motion, step.observations, relative);
    ASSERT_TRUE(a.ok()) << a.status().message();
    ASSERT_TRUE(b.ok()) << b.status().message();
    EXPECT_EQ(a->lines_used, b->lines_used);
    EXPECT_GE(a->lines_used, 2);
    if (std::lround(step.stamp_s * 10) % 7 == 0) {
      EXPECT_EQ(a->lines_rejected, 0) << "the outlier enters the solve, under the loss";
      ++robust_lines;
    }
    const std::vector<core::SE2> poses_chain = chain.WindowPoses();
    const std::vector<core::SE2> poses_ceres = ceres.WindowPoses();
    ASSERT_EQ(poses_chain.size(), poses_ceres.size());
    for (size_t i = 0; i < poses_chain.size(); ++i) {
      ASSERT_TRUE(poses_chain[i].IsApprox(poses_ceres[i], 1e-6, 1e-6))
          << "keyframe " << step.stamp_s << " pose " << i << ": "
          << poses_chain[i].Vector().transpose() << " vs " << poses_ceres[i].Vector().transpose();
    }
    const core::Matrix3& P_chain = chain.Latest().covariance;
    const core::Matrix3& P_ceres = ceres.Latest().covariance;
    ASSERT_LT((P_chain - P_ceres).norm(), 1e-6 * P_ceres.norm()) << "keyframe " << step.stamp_s;
  }
  EXPECT_GE(robust_lines, 4);
  if (window_s < 10.0) {
    EXPECT_LE(chain.WindowSize(), static_cast<int>(window_s / 0.1) + 2);
  }
}

TEST(SlidingWindowChain, EqualsCeresBatchWithoutMarginalization) {
  ExpectChainEqualsCeres(1e6, false);
}

TEST(SlidingWindowChain, EqualsCeresBatchWithMarginalization) {
  ExpectChainEqualsCeres(1.0, false);
}

TEST(SlidingWindowChain, EqualsCeresBatchWithARankDeficientRelativeMeasurement) {
  ExpectChainEqualsCeres(1.0, true);
}

}  // namespace
}  // namespace groundline::localization
