#include "groundline/localization/keyframe_selector.h"

#include <gtest/gtest.h>

#include <limits>
#include <numbers>

#include "groundline/localization/odometry_integrator.h"
#include "test_units.h"

namespace groundline::localization {
namespace {

using core::SE2;
using ::groundline::testing::kDeg;

TEST(KeyframeSelector, DefaultThresholds) {
  const KeyframeSelector selector(KeyframeSelector::Options{});
  EXPECT_DOUBLE_EQ(selector.options().min_translation_m, 0.20);
  EXPECT_DOUBLE_EQ(selector.options().min_rotation_rad, 5.0 * kDeg);
  EXPECT_FALSE(selector.IsKeyframeDue(SE2()));
  EXPECT_FALSE(selector.IsKeyframeDue(SE2(0.199, 0.0, 0.0)));
  EXPECT_TRUE(selector.IsKeyframeDue(SE2(0.20, 0.0, 0.0)));
  EXPECT_FALSE(selector.IsKeyframeDue(SE2(0.14, 0.14, 0.0)));  // 0.198 m
  EXPECT_TRUE(selector.IsKeyframeDue(SE2(-0.15, 0.15, 0.0)));  // 0.212 m, reversing
  EXPECT_FALSE(selector.IsKeyframeDue(SE2(0.0, 0.0, 4.9 * kDeg)));
  EXPECT_TRUE(selector.IsKeyframeDue(SE2(0.0, 0.0, 5.0 * kDeg)));
  EXPECT_TRUE(selector.IsKeyframeDue(SE2(0.0, 0.0, -5.1 * kDeg)));
  // A full turn back to the keyframe heading is no rotation.
  EXPECT_FALSE(selector.IsKeyframeDue(SE2(0.0, 0.0, 2.0 * std::numbers::pi - 1.0 * kDeg)));
}

TEST(KeyframeSelector, EveryTwentyCentimetresOnAStraightDrive) {
  const DiffDriveParams drive;
  OdometryIntegrator odometry(drive, OdometryNoiseParams{});
  const KeyframeSelector selector(KeyframeSelector::Options{});
  int keyframes = 0;
  for (int i = 0; i < 300; ++i) {  // 3 m in 1 cm steps
    odometry.Integrate(WheelsFromArc(drive, 0.01, 0.0));
    if (selector.IsKeyframeDue(odometry.SinceKeyframe().T_start_end)) {
      const RelativeMotion span = odometry.StartKeyframe();
      EXPECT_NEAR(span.T_start_end.x(), 0.20, 1e-9);
      ++keyframes;
    }
  }
  EXPECT_EQ(keyframes, 15);
}

TEST(KeyframeSelector, TurningInPlaceTriggersOnRotation) {
  const DiffDriveParams drive;
  OdometryIntegrator odometry(drive, OdometryNoiseParams{});
  KeyframeSelector::Options options;
  options.min_rotation_rad = 10.0 * kDeg;
  const KeyframeSelector selector(options);
  int keyframes = 0;
  for (int i = 0; i < 360; ++i) {  // one full turn in 1 degree steps
    odometry.Integrate(WheelsFromArc(drive, 0.0, 1.0 * kDeg));
    if (selector.IsKeyframeDue(odometry.SinceKeyframe().T_start_end)) {
      EXPECT_NEAR(odometry.StartKeyframe().T_start_end.yaw(), 10.0 * kDeg, 1e-9);
      ++keyframes;
    }
  }
  EXPECT_EQ(keyframes, 36);
}

TEST(KeyframeSelector, ValidateNamesTheBadField) {
  KeyframeSelector::Options options;
  EXPECT_TRUE(options.Validate().ok());
  options.min_translation_m = 0.0;
  EXPECT_EQ(options.Validate().message(),
            "KeyframeSelector::Options.min_translation_m: expected a finite value > 0 [m], got 0");
  options = KeyframeSelector::Options{};
  options.min_rotation_rad = 4.0;
  EXPECT_EQ(options.Validate().message(),
            "KeyframeSelector::Options.min_rotation_rad: expected a value in (0, pi] [rad], got 4");
  options.min_rotation_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(options.Validate().ok());
}

}  // namespace
}  // namespace groundline::localization
