#include "groundline/localization/dead_reckoning.h"
#include "test_units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace groundline::localization {
namespace {

using ::groundline::testing::kPi;

// Exact wheel increments for driving a circle of radius_m (left turn) at
// 1 cm per reading, 100 readings per second, starting at t = 0.01 s.
std::vector<core::WheelEncoderReading> CircleReadings(const DiffDriveParams& drive,
                                                      double radius_m, int n) {
  const double ds = 2.0 * kPi * radius_m / n;
  const double dtheta = ds / radius_m;
  const double right = (ds + 0.5 * drive.track_m * dtheta) / drive.wheel_radius_m;
  const double left = (ds - 0.5 * drive.track_m * dtheta) / drive.wheel_radius_m;
  std::vector<core::WheelEncoderReading> readings;
  for (int i = 1; i <= n; ++i) readings.push_back({0.01 * i, left, right});
  return readings;
}

TEST(DeadReckoning, FollowsACircleAndClosesIt) {
  DeadReckoningOptions options;
  const double radius_m = 3.0;
  const int n = 1885;  // about 1 cm per reading
  const core::StampedPose start{0.0, core::SE2(10.0, -4.0, 0.7), std::nullopt};
  const core::Result<DeadReckoningResult> result =
      DeadReckon(CircleReadings(options.drive, radius_m, n), start, options);
  ASSERT_TRUE(result.ok()) << result.message();
  ASSERT_EQ(result->odometry_rate.size(), static_cast<std::size_t>(n + 1));
  // Centre of the circle: radius_m to the left of the start pose.
  const core::Vector2 centre = start.pose * core::Vector2(0.0, radius_m);
  for (const core::StampedPose& p : result->odometry_rate) {
    EXPECT_NEAR((p.pose.translation() - centre).norm(), radius_m, 1e-9);
  }
  EXPECT_TRUE(result->odometry_rate.back().pose.IsApprox(start.pose, 1e-9, 1e-9));
  EXPECT_NEAR(result->path_length_m, 2.0 * kPi * radius_m, 1e-9);
}

TEST(DeadReckoning, CovarianceGrowsAndKeyframesFollowTheSelector) {
  DeadReckoningOptions options;
  const core::Result<DeadReckoningResult> result = DeadReckon(
      CircleReadings(options.drive, 3.0, 1885), {0.0, core::SE2(), std::nullopt}, options);
  ASSERT_TRUE(result.ok()) << result.message();
  double previous_trace = -1.0;
  for (const core::StampedPose& p : result->odometry_rate) {
    ASSERT_TRUE(p.covariance.has_value());
    EXPECT_GT(p.covariance->trace(), previous_trace);
    previous_trace = p.covariance->trace();
  }
  // On a 3 m radius circle 0.20 m of chord comes before 5 deg (0.26 m of arc),
  // so consecutive keyframes are 0.20 m apart, plus less than one 1 cm reading.
  const std::vector<core::StampedPose>& keyframes = result->keyframes;
  ASSERT_GE(keyframes.size(), 80u);
  for (std::size_t k = 1; k < keyframes.size(); ++k) {
    const core::SE2 step = keyframes[k - 1].pose.Between(keyframes[k].pose);
    EXPECT_GE(step.translation().norm(), options.keyframes.min_translation_m - 1e-12);
    EXPECT_LT(step.translation().norm(), options.keyframes.min_translation_m + 0.011);
  }
}

TEST(DeadReckoning, SkipsReadingsBeforeTheInitialStampAndRejectsDisorder) {
  DeadReckoningOptions options;
  std::vector<core::WheelEncoderReading> readings = CircleReadings(options.drive, 3.0, 100);
  const core::StampedPose start{0.5, core::SE2(), std::nullopt};
  core::Result<DeadReckoningResult> result = DeadReckon(readings, start, options);
  ASSERT_TRUE(result.ok()) << result.message();
  EXPECT_EQ(result->odometry_rate.size(), 51u);  // readings at 0.51 .. 1.00 s, plus the start

  std::swap(readings[70], readings[71]);
  result = DeadReckon(readings, start, options);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.message().find("reading 71"), std::string::npos) << result.message();

  options.drive.track_m = -1.0;
  result = DeadReckon(CircleReadings(DiffDriveParams{}, 3.0, 10), start, options);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.message().find("track_m"), std::string::npos) << result.message();
}

}  // namespace
}  // namespace groundline::localization
