// Wheel-encoder simulator: slip events and input validation.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "encoder_test_paths.h"
#include "groundline/sim/wheel_encoders.h"

namespace groundline::sim {
namespace {

using namespace testing;  // NOLINT: the shared test helpers

TEST(WheelEncoders, SlipEventsCauseDetectableJumps) {
  const DiffDriveParams drive;
  const core::Trajectory truth = TruthFromSegments(WarehouseRun());
  WheelEncoderOptions sim;
  sim.radius_scale_stddev = 1e-3;
  sim.wheel_variance_m2_per_m = 1e-5;
  sim.seed = 77;
  const core::Result<WheelEncoderLog> clean = SimulateWheelEncoders(truth, drive, sim);
  sim.slip_rate_per_m = 0.25;
  sim.slip_mean_m = 0.03;
  const core::Result<WheelEncoderLog> slipping = SimulateWheelEncoders(truth, drive, sim);
  ASSERT_TRUE(clean.ok() && slipping.ok());
  ASSERT_GE(slipping->slips.size(), 3u);  // about 5 expected over 20.7 m
  EXPECT_TRUE(clean->slips.empty());
  EXPECT_EQ(clean->left_radius_scale, slipping->left_radius_scale);  // same streams

  // 1. The heading of the slipping run departs from the clean run by exactly
  // the slips' spurious travel / B (as seen through each wheel's radius
  // error), jumping at each event; both runs carry < 1 tick of quantization.
  const OdometryNoiseParams noise = CoveringNoise(sim, drive.track_m, MaxWheelTravel(truth, drive));
  const std::vector<SE2> a = DeadReckon(*clean, truth[0].pose, drive, noise);
  const std::vector<SE2> b = DeadReckon(*slipping, truth[0].pose, drive, noise);
  const double tick_heading_rad = 2.0 * drive.wheel_radius_m * 2.0 * kPi / 4096.0 / drive.track_m;
  double expected_rad = 0.0;
  size_t next_slip = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    while (next_slip < slipping->slips.size() &&
           slipping->slips[next_slip].reading_index == static_cast<int>(k)) {
      const SlipEvent& s = slipping->slips[next_slip++];
      const double scale =
          s.left_wheel ? slipping->left_radius_scale : slipping->right_radius_scale;
      expected_rad += (s.left_wheel ? -1.0 : 1.0) * s.spurious_travel_m / scale / drive.track_m;
    }
    ASSERT_NEAR(core::WrapAngle(b[k].yaw() - a[k].yaw()), expected_rad, tick_heading_rad)
        << "reading " << k;
  }

  // 2. Each slip reading is an outlier of the odometry increment against the
  // true motion under the increment covariance ((ds, dtheta), 2 dof), while
  // ordinary readings almost never are.
  constexpr double kChi2Dof2P9999 = 18.42;
  int false_alarms = 0;
  next_slip = 0;
  for (size_t k = 0; k < slipping->readings.size(); ++k) {
    const Vector3 step = truth[k].pose.Between(truth[k + 1].pose).Log();
    const localization::OdometryIncrement inc =
        localization::IncrementFromWheels(drive, noise, slipping->readings[k].increment);
    const double e_s = inc.distance_m - step.x();
    const double e_theta = inc.rotation_rad - step.z();
    const double d2 = e_s * e_s / inc.covariance(0, 0) + e_theta * e_theta / inc.covariance(2, 2);
    const bool is_slip = next_slip < slipping->slips.size() &&
                         slipping->slips[next_slip].reading_index == static_cast<int>(k);
    if (is_slip) {
      EXPECT_GT(d2, kChi2Dof2P9999) << "slip at reading " << k << " not detectable";
      ++next_slip;
    } else if (d2 > kChi2Dof2P9999) {
      ++false_alarms;
    }
  }
  EXPECT_LT(false_alarms, 0.005 * slipping->readings.size());
}

TEST(WheelEncoders, RejectsInfeasibleTruth) {
  const DiffDriveParams drive;
  core::Trajectory truth = TruthFromSegments({{1.0, 0.0, 10}});
  truth[5].pose = truth[5].pose * SE2(0.0, 0.01, 0.0);  // a sideways hop
  core::Result<WheelEncoderLog> log = SimulateWheelEncoders(truth, drive, WheelEncoderOptions{});
  ASSERT_FALSE(log.ok());
  EXPECT_NE(log.message().find("truth trajectory pose 5 (stamp 0.05 s): moves 0.01 m sideways"),
            std::string::npos)
      << log.message();

  truth = TruthFromSegments({{1.0, 0.0, 10}});
  truth[3].stamp_s = truth[2].stamp_s;
  log = SimulateWheelEncoders(truth, drive, WheelEncoderOptions{});
  ASSERT_FALSE(log.ok());
  EXPECT_NE(log.message().find("truth trajectory pose 3: field 'stamp_s': expected > 0.02"),
            std::string::npos)
      << log.message();

  log = SimulateWheelEncoders(core::Trajectory{}, drive, WheelEncoderOptions{});
  ASSERT_TRUE(log.ok());
  EXPECT_TRUE(log->readings.empty());
}

TEST(WheelEncoderOptions, ValidateNamesTheBadField) {
  EXPECT_TRUE(WheelEncoderOptions{}.Validate().ok());
  WheelEncoderOptions options;
  options.ticks_per_revolution = 0;
  EXPECT_EQ(options.Validate().message(),
            "WheelEncoderOptions.ticks_per_revolution: expected an integer >= 1, got 0");
  options = WheelEncoderOptions{};
  options.radius_scale_stddev = 0.2;
  EXPECT_EQ(options.Validate().message(),
            "WheelEncoderOptions.radius_scale_stddev: expected a value in [0, 0.1), got 0.2");
  options = WheelEncoderOptions{};
  options.wheel_variance_m2_per_m = -1e-5;
  EXPECT_NE(options.Validate().message().find("wheel_variance_m2_per_m"), std::string::npos);
  options = WheelEncoderOptions{};
  options.slip_rate_per_m = std::nan("");
  EXPECT_NE(options.Validate().message().find("slip_rate_per_m"), std::string::npos);
  options = WheelEncoderOptions{};
  options.max_lateral_step_m = 0.0;
  EXPECT_NE(options.Validate().message().find("max_lateral_step_m"), std::string::npos);
}

}  // namespace
}  // namespace groundline::sim
