// The smoother without observations is dead reckoning: its newest pose and
// covariance equal the odometry's, whether the chain is kept in the window or
// marginalized into the prior (a differential check of the marginal prior
// and the newest-pose covariance); odometry-rate propagation; options.
#include "groundline/localization/sliding_window_smoother.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace groundline::localization {
namespace {

std::vector<RelativeMotion> RandomMotions(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ds(0.15, 0.25);
  std::uniform_real_distribution<double> dtheta(-0.08, 0.08);
  const OdometryNoiseParams noise;
  std::vector<RelativeMotion> motions;
  for (int i = 0; i < n; ++i) {
    RelativeMotion motion;
    const double d = ds(rng);
    const double t = dtheta(rng);
    motion.T_start_end = core::SE2::Exp(Eigen::Vector3d(d, 0.0, t));
    motion.covariance = IncrementCovariance(noise, d, t);
    motions.push_back(motion);
  }
  return motions;
}

TEST(SlidingWindowSmoother, WithoutObservationsItIsDeadReckoningWithOrWithoutMarginalization) {
  const std::vector<RelativeMotion> motions = RandomMotions(60, 51);
  const core::SE2 start(2.0, 1.0, 0.4);
  const core::Matrix3 start_covariance = Eigen::Vector3d(1e-4, 2e-4, 1e-5).asDiagonal();
  SmootherOptions keep_all;
  keep_all.window_s = 1e6;
  SmootherOptions short_window;
  short_window.window_s = 1.0;  // keyframes every 0.1 s: ~10 in the window
  for (SmootherOptions* options : {&keep_all, &short_window}) {
    // Floors far below the increments' own noise, so the chain equals dead reckoning.
    options->odometry_sigma_floor_m = 1e-7;
    options->odometry_sigma_floor_rad = 1e-7;
  }
  SlidingWindowSmoother full(keep_all, Atlas());
  SlidingWindowSmoother marginalizing(short_window, Atlas());
  full.Initialize(0.0, start, start_covariance);
  marginalizing.Initialize(0.0, start, start_covariance);
  PoseEstimate dead_reckoning{0.0, start, start_covariance};
  for (size_t i = 0; i < motions.size(); ++i) {
    const double stamp_s = 0.1 * static_cast<double>(i + 1);
    dead_reckoning = PropagateFromKeyframe(dead_reckoning, motions[i], stamp_s);
    ASSERT_TRUE(full.AddKeyframe(stamp_s, motions[i], {}).ok());
    const auto health = marginalizing.AddKeyframe(stamp_s, motions[i], {});
    ASSERT_TRUE(health.ok());
    EXPECT_LE(health->window_size, 12);
  }
  EXPECT_EQ(full.WindowSize(), 61);
  for (const SlidingWindowSmoother* smoother : {&full, &marginalizing}) {
    const PoseEstimate& latest = smoother->Latest();
    EXPECT_TRUE(latest.T_map_base.IsApprox(dead_reckoning.T_map_base, 1e-6, 1e-6));
    EXPECT_LT((latest.covariance - dead_reckoning.covariance).norm(),
              1e-6 * dead_reckoning.covariance.norm());
  }
}

// A rank-deficient relative measurement (a corridor scan match: lateral and
// heading known, nothing along the aisle) corrects the odometry's lateral and
// heading drift and leaves the along-track distance to the odometry, also
// after the corrected keyframes are marginalized into the prior.
TEST(SlidingWindowSmoother, RankDeficientRelativeMeasurementCorrectsOnlyItsDirections) {
  const core::SE2 true_step(0.2, 0.0, 0.0);
  RelativeMotion motion;  // biased odometry: drifts sideways and turns
  motion.T_start_end = core::SE2(0.21, 0.01, 0.002);
  motion.covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  RelativePoseMeasurement scan;
  scan.T_prev_curr = true_step;
  scan.sqrt_information = Eigen::Vector3d(0.0, 1e4, 1e4).asDiagonal();  // no x row
  for (const double window_s : {1e6, 0.5}) {
    SmootherOptions options;
    options.window_s = window_s;
    SlidingWindowSmoother smoother(options, Atlas());
    smoother.Initialize(0.0, core::SE2(), core::Matrix3::Identity() * 1e-8);
    const int n = 20;
    for (int i = 1; i <= n; ++i) {
      const auto health = smoother.AddKeyframe(0.1 * i, motion, {}, scan);
      ASSERT_TRUE(health.ok()) << health.status().message();
      EXPECT_TRUE(health->relative_measurement_used);
    }
    const PoseEstimate& latest = smoother.Latest();
    EXPECT_NEAR(latest.T_map_base.x(), 0.21 * n, 1e-3) << "window " << window_s;
    // Dead reckoning ends ~0.6 m to the side and 0.04 rad off; the scan rows
    // (sigma 1e-4 per step against the odometry's 1e-2) leave 1e-4 of that.
    EXPECT_NEAR(latest.T_map_base.y(), 0.0, 5e-4) << "window " << window_s;
    EXPECT_NEAR(latest.T_map_base.yaw(), 0.0, 1e-4) << "window " << window_s;
    // Along-track uncertainty grows like the odometry's; lateral and heading
    // grow like the scan's random walk (20 steps of 1e-8 rad^2), far below the
    // odometry's (20 x 1e-5 rad^2).
    EXPECT_NEAR(latest.covariance(0, 0), n * 1e-4, 0.05 * n * 1e-4);
    EXPECT_LT(latest.covariance(1, 1), 0.01 * n * 1e-4);
    EXPECT_NEAR(latest.covariance(2, 2), n * 1e-8, 0.1 * n * 1e-8);
  }
}

// A keyframe held for a loop closure stays in the window past window_s (and
// so does everything newer); once released the window shrinks back, and the
// estimate equals that of a smoother that never held anything (holding only
// delays marginalization, which is exact here: dead reckoning).
TEST(SlidingWindowSmoother, AHeldKeyframeIsNotMarginalizedUntilReleased) {
  const std::vector<RelativeMotion> motions = RandomMotions(40, 7);
  SmootherOptions options;
  options.window_s = 1.0;  // ~10 keyframes
  SlidingWindowSmoother held(options, Atlas());
  SlidingWindowSmoother plain(options, Atlas());
  const core::Matrix3 start_covariance = core::Matrix3::Identity() * 1e-4;
  held.Initialize(0.0, core::SE2(), start_covariance);
  plain.Initialize(0.0, core::SE2(), start_covariance);
  EXPECT_FALSE(held.HoldKeyframe(0.05));  // no such keyframe
  for (size_t i = 0; i < motions.size(); ++i) {
    const double stamp_s = 0.1 * static_cast<double>(i + 1);
    ASSERT_TRUE(held.AddKeyframe(stamp_s, motions[i], {}).ok());
    ASSERT_TRUE(plain.AddKeyframe(stamp_s, motions[i], {}).ok());
    if (i == 4) {
      ASSERT_TRUE(held.HoldKeyframe(stamp_s));
    }
    if (i == 29) {
      EXPECT_EQ(held.WindowSize(), 26);  // keyframes 0.5 s ... 3.0 s
      ASSERT_TRUE(held.HoldKeyframe(0.5, false));
    }
  }
  EXPECT_EQ(held.WindowSize(), plain.WindowSize());
  EXPECT_LE(held.WindowSize(), 12);
  EXPECT_TRUE(held.Latest().T_map_base.IsApprox(plain.Latest().T_map_base, 1e-9, 1e-9));
  EXPECT_LT((held.Latest().covariance - plain.Latest().covariance).norm(),
            1e-6 * plain.Latest().covariance.norm());
}

TEST(SlidingWindowSmoother, NonFiniteRelativeMeasurementIsAnError) {
  SlidingWindowSmoother smoother{SmootherOptions(), Atlas()};
  smoother.Initialize(0.0, core::SE2(), core::Matrix3::Identity() * 1e-4);
  RelativeMotion motion;
  motion.T_start_end = core::SE2(0.2, 0.0, 0.0);
  motion.covariance = core::Matrix3::Identity() * 1e-4;
  RelativePoseMeasurement scan;
  scan.sqrt_information(0, 0) = std::numeric_limits<double>::quiet_NaN();
  const auto health = smoother.AddKeyframe(0.1, motion, {}, scan);
  ASSERT_FALSE(health.ok());
  EXPECT_NE(health.status().message().find("relative measurement"), std::string::npos);
}

TEST(PropagateFromKeyframe, ComposesThePoseAndTransportsTheCovariance) {
  PoseEstimate keyframe{1.0, core::SE2(1.0, 2.0, 0.3), core::Matrix3::Zero()};
  keyframe.covariance(2, 2) = 1e-4;  // heading only
  RelativeMotion motion;
  motion.T_start_end = core::SE2(2.0, 0.0, 0.0);
  motion.covariance = core::Matrix3::Identity() * 1e-6;
  const PoseEstimate out = PropagateFromKeyframe(keyframe, motion, 1.5);
  EXPECT_EQ(out.stamp_s, 1.5);
  EXPECT_TRUE(out.T_map_base.IsApprox(keyframe.T_map_base * motion.T_start_end));
  // A heading error of the keyframe moves a pose 2 m ahead sideways by 2 m * dtheta.
  EXPECT_NEAR(out.covariance(1, 1), 4.0 * 1e-4 + 1e-6, 1e-12);
  EXPECT_NEAR(out.covariance(0, 0), 1e-6, 1e-12);
  EXPECT_NEAR(out.covariance(2, 2), 1e-4 + 1e-6, 1e-12);
}

TEST(SmootherOptions, ValidateNamesTheField) {
  SmootherOptions options;
  EXPECT_TRUE(options.Validate().ok());
  options.window_s = 0.0;
  EXPECT_NE(options.Validate().message().find("window_s"), std::string::npos);
  options = SmootherOptions();
  options.step_tolerance = 0.0;
  EXPECT_NE(options.Validate().message().find("step_tolerance"), std::string::npos);
  options = SmootherOptions();
  options.association.gate_chi2 = -1.0;
  EXPECT_NE(options.Validate().message().find("gate_chi2"), std::string::npos);
}

}  // namespace
}  // namespace groundline::localization
