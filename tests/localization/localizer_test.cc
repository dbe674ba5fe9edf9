// The causal localizer (localization/localizer.h) driven one reading at a
// time: frame-time keyframes, drops that leave the estimate untouched, the
// odometry-rate pose, and the setup checks.
#include "groundline/localization/localizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "lidar_test_world.h"

#include "groundline/core/trajectory_association.h"
#include "groundline/localization/atlas_walls.h"
#include "groundline/localization/odometry_integrator.h"

namespace groundline::localization {
namespace {

constexpr double kRadiusM = 0.125;
constexpr double kPeriodS = 0.01;

// Straight at 1 m/s: both wheels roll 1 cm per 10 ms reading.
core::WheelEncoderReading Straight(int k) {
  const double delta_rad = 0.01 / kRadiusM;
  return {k * kPeriodS, delta_rad, delta_rad};
}

LocalizerSetup Vehicle() {
  LocalizerSetup setup;
  setup.drive.wheel_radius_m = kRadiusM;
  setup.drive.track_m = 0.76;
  return setup;
}

core::Matrix3 StartCovariance() { return core::Vector3(1e-6, 1e-6, 1e-6).asDiagonal(); }

std::unique_ptr<Localizer> Make(LocalizerMode mode, LocalizerOptions options = {}) {
  options.mode = mode;
  core::Result<std::unique_ptr<Localizer>> made = Localizer::Create(options, Vehicle());
  EXPECT_TRUE(made.ok()) << made.message();
  EXPECT_TRUE((*made)->SetInitialPose(0.0, core::SE2(), StartCovariance()).ok());
  return std::move(made).value();
}

TEST(Localizer, AFrameBetweenReadingsPutsTheKeyframeAtTheFramesTime) {
  std::unique_ptr<Localizer> localizer = Make(LocalizerMode::kLines);
  std::vector<KeyframeOutput> keyframes;
  for (int k = 1; k <= 40; ++k) {
    if (k == 31) {
      // A frame at 0.305 s, between the readings at 0.30 and 0.31 s, with
      // nothing seen: the keyframe is at its time, 0.305 m along.
      ConvertedObservations seen;
      seen.observations.stamp_s = 0.305;
      localizer->AddFloorObservations(seen);
    }
    if (auto out = localizer->AddWheelReading(Straight(k))) keyframes.push_back(*out);
  }
  ASSERT_EQ(keyframes.size(), 1u);
  EXPECT_DOUBLE_EQ(keyframes[0].stamp_s, 0.305);
  ASSERT_TRUE(keyframes[0].frame_stamp_s.has_value());
  EXPECT_NEAR(keyframes[0].pose.T_map_base.x(), 0.305, 1e-9);
  EXPECT_NEAR(keyframes[0].pose.T_map_base.y(), 0.0, 1e-12);
  // The odometry continues from the keyframe to the newest reading.
  EXPECT_NEAR(localizer->Current().T_map_base.x(), 0.40, 1e-9);
  EXPECT_DOUBLE_EQ(localizer->Current().stamp_s, 0.40);
  EXPECT_EQ(localizer->counters().frames_used, 1);
}

TEST(Localizer, BadAndOutOfOrderReadingsAreDroppedAndCountedAndChangeNothing) {
  std::unique_ptr<Localizer> clean = Make(LocalizerMode::kOdometry);
  std::unique_ptr<Localizer> noisy = Make(LocalizerMode::kOdometry);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<KeyframeOutput> clean_out, noisy_out;
  for (int k = 1; k <= 300; ++k) {
    if (auto out = clean->AddWheelReading(Straight(k))) clean_out.push_back(*out);
    if (auto out = noisy->AddWheelReading(Straight(k))) noisy_out.push_back(*out);
    if (k % 50 == 0) {
      EXPECT_FALSE(noisy->AddWheelReading(Straight(k)));               // duplicate
      EXPECT_FALSE(noisy->AddWheelReading(Straight(k - 10)));          // 0.1 s behind: out of order
      EXPECT_FALSE(noisy->AddWheelReading({k * kPeriodS, nan, 0.0}));  // NaN at a taken stamp
      EXPECT_FALSE(noisy->AddWheelReading({nan, 0.0, 0.0}));           // NaN stamp
    }
  }
  ASSERT_EQ(noisy_out.size(), clean_out.size());
  ASSERT_GT(clean_out.size(), 10u);  // 3 m at a keyframe every 0.2 m
  for (std::size_t i = 0; i < clean_out.size(); ++i) {
    EXPECT_EQ(noisy_out[i].stamp_s, clean_out[i].stamp_s);
    EXPECT_EQ(noisy_out[i].pose.T_map_base.x(), clean_out[i].pose.T_map_base.x());
    EXPECT_EQ(noisy_out[i].pose.covariance, clean_out[i].pose.covariance);
  }
  const LocalizerCounters& c = noisy->counters();
  EXPECT_EQ(c.wheel_readings, 300 + 6 * 4);
  EXPECT_EQ(c.wheel_dropped_duplicate, 6);
  EXPECT_EQ(c.wheel_dropped_out_of_order, 6);
  EXPECT_EQ(c.clock_jumps, 0);
  EXPECT_EQ(c.wheel_dropped_non_finite, 6 * 2);
  EXPECT_NEAR(noisy->Current().T_map_base.x(), 3.0, 1e-9);
}

TEST(Localizer, LateReadingsWithinTheToleranceAreMergedSoThatNoMotionIsLost) {
  std::unique_ptr<Localizer> localizer = Make(LocalizerMode::kOdometry);
  // Every 7th pair of readings swapped in transport; the second of a swapped
  // pair is late by one reading (10 ms, tolerance 50 ms), then sent again.
  int swapped = 0;
  for (int k = 1; k <= 300; ++k) {
    if (k % 7 == 0 && k < 300) {
      localizer->AddWheelReading(Straight(k + 1));
      localizer->AddWheelReading(Straight(k));
      localizer->AddWheelReading(Straight(k));  // a duplicate of the late one
      ++swapped;
      ++k;
      continue;
    }
    localizer->AddWheelReading(Straight(k));
  }
  const LocalizerCounters& c = localizer->counters();
  EXPECT_EQ(c.wheel_late_merged, swapped);
  EXPECT_EQ(c.wheel_dropped_duplicate, swapped);
  EXPECT_EQ(c.wheel_dropped_out_of_order, 0);
  // Each late reading's centimetre joined the next one: 3 m in all.
  EXPECT_NEAR(localizer->Current().T_map_base.x(), 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(localizer->Current().stamp_s, 3.0);
}

TEST(Localizer, ABackwardClockJumpKeepsTheEstimateContinuousOnTheSourcesNewClock) {
  LocalizerOptions options;
  options.mode = LocalizerMode::kLines;
  options.blind_keyframe_m = 0.5;
  std::unique_ptr<Localizer> localizer = std::move(Localizer::Create(options, Vehicle())).value();
  ASSERT_TRUE(localizer->SetInitialPose(0.0, core::SE2(), StartCovariance()).ok());
  std::vector<KeyframeOutput> keyframes;
  for (int k = 1; k <= 200; ++k) {
    if (auto out = localizer->AddWheelReading(Straight(k))) keyframes.push_back(*out);
  }
  // A few stray old readings are not a jump: dropped.
  for (int k = 100; k < 103; ++k) localizer->AddWheelReading(Straight(k));
  localizer->AddWheelReading(Straight(201));
  EXPECT_EQ(localizer->counters().wheel_dropped_out_of_order, 3);
  EXPECT_EQ(localizer->counters().clock_jumps, 0);
  const std::size_t before_jump = keyframes.size();
  // At 2.01 s the source's clock steps back by 1000 s; the drive goes on.
  constexpr double kJumpS = 1000.0;
  for (int k = 202; k <= 400; ++k) {
    core::WheelEncoderReading r = Straight(k);
    r.stamp_s -= kJumpS;
    if (auto out = localizer->AddWheelReading(r)) keyframes.push_back(*out);
    if (k == 280) {
      // A frame on the new clock is used; one still on the old clock is
      // far ahead of the odometry: dropped.
      ConvertedObservations seen;
      seen.observations.stamp_s = 2.805 - kJumpS;
      localizer->AddFloorObservations(seen);
      seen.observations.stamp_s = 2.815;
      localizer->AddFloorObservations(seen);
    }
  }
  const LocalizerCounters& c = localizer->counters();
  EXPECT_EQ(c.clock_jumps, 1);
  EXPECT_EQ(c.wheel_dropped_out_of_order, 3);
  EXPECT_EQ(c.frames_dropped_ahead, 1);
  EXPECT_EQ(c.frames_used, 1);
  // No motion lost over the jump (the readings that revealed it are taken),
  // and the outputs carry the new clock.
  EXPECT_NEAR(localizer->Current().T_map_base.x(), 4.0, 1e-9);
  EXPECT_NEAR(localizer->Current().stamp_s, 4.0 - kJumpS, 1e-9);
  ASSERT_GE(keyframes.size(), before_jump + 3);
  for (std::size_t i = before_jump; i < keyframes.size(); ++i) {
    EXPECT_LT(keyframes[i].stamp_s, 4.0 - kJumpS + 1e-9);
    EXPECT_NEAR(keyframes[i].pose.T_map_base.x(), keyframes[i].stamp_s + kJumpS, 1e-6);
    if (i > before_jump) {
      EXPECT_GT(keyframes[i].stamp_s, keyframes[i - 1].stamp_s);
    }
  }
  const std::optional<PoseEstimate> mid = localizer->PoseAt(3.555 - kJumpS);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->T_map_base.x(), 3.555, 1e-9);
  EXPECT_DOUBLE_EQ(mid->stamp_s, 3.555 - kJumpS);
}

TEST(Localizer, AGapInTheReadingsIsCountedAndWidensTheOdometryByTheUnknownMotion) {
  std::unique_ptr<Localizer> localizer = Make(LocalizerMode::kOdometry);
  localizer->AddWheelReading(Straight(1));
  localizer->AddWheelReading(Straight(2));
  const double before_m2 = localizer->Current().covariance(0, 0);
  localizer->AddWheelReading(Straight(200));  // 1.98 s later: readings lost
  EXPECT_EQ(localizer->counters().odometry_gaps, 1);
  // 2 m/s over the gap: a sigma of about 4 m along and across.
  const LocalizerOptions defaults;
  const double expected_m = defaults.odometry_gap_speed_mps * 1.98;
  EXPECT_NEAR(std::sqrt(localizer->Current().covariance(0, 0) - before_m2), expected_m, 0.05);
  EXPECT_GT(std::sqrt(localizer->Current().covariance(2, 2)), 1.9);
}

TEST(Localizer, FrozenEncodersAreDroppedAndTheEstimateCoastsOverThemWithAGrowingCovariance) {
  std::unique_ptr<Localizer> localizer = Make(LocalizerMode::kOdometry);
  for (int k = 1; k <= 50; ++k) localizer->AddWheelReading(Straight(k));  // 1 m/s
  const double before_m2 = localizer->Current().covariance(0, 0);
  for (int k = 51; k <= 150; ++k) localizer->AddWheelReading({k * kPeriodS, 0.0, 0.0});
  EXPECT_EQ(localizer->counters().wheel_dropped_frozen, 100);
  EXPECT_EQ(localizer->counters().wheel_coasted, 100);
  EXPECT_TRUE(localizer->Sensors().odometry_frozen);
  EXPECT_FALSE(localizer->Sensors().odometry_ok);
  // The outputs went on at the last wheel speeds: 1 m/s for the frozen second.
  EXPECT_DOUBLE_EQ(localizer->Current().stamp_s, 1.50);
  EXPECT_NEAR(localizer->Current().T_map_base.x(), 1.50, 1e-9);
  // The speed error grows with the time since the last good reading: 2 m/s x 1 s.
  const LocalizerOptions defaults;
  EXPECT_NEAR(std::sqrt(localizer->Current().covariance(0, 0) - before_m2),
              defaults.odometry_gap_speed_mps * 1.0, 0.05);
  localizer->AddWheelReading(Straight(151));  // the wheels report again
  EXPECT_FALSE(localizer->Sensors().odometry_frozen);
  EXPECT_EQ(localizer->counters().odometry_gaps, 0);
  EXPECT_NEAR(localizer->Current().T_map_base.x(), 1.51, 1e-9);

  // A real stop decelerates: zero increments after a slow reading are kept.
  std::unique_ptr<Localizer> stopping = Make(LocalizerMode::kOdometry);
  const double slow_rad = 0.0005 / kRadiusM;  // 5 cm/s
  stopping->AddWheelReading({0.01, slow_rad, slow_rad});
  for (int k = 2; k <= 100; ++k) stopping->AddWheelReading({k * kPeriodS, 0.0, 0.0});
  EXPECT_EQ(stopping->counters().wheel_dropped_frozen, 0);
  EXPECT_FALSE(stopping->Sensors().odometry_frozen);
}

// A wheel that spins for one reading (the left one reports 7 cm backwards
// while the vehicle drives straight at 1 m/s): taken, the heading would turn
// by 7 cm over the 0.76 m track, 5.3 deg; dropped as a slip, the estimate
// coasts over the reading at the last wheel speeds and stays straight.
// Speeds that change as a vehicle's do, a start while driving, and a turn
// begun as a vehicle begins one are no slip.
TEST(Localizer, AWheelSpeedStepNoVehicleMakesIsASlipThatIsDroppedAndCoastedOver) {
  const auto drive = [](double slip_speed_difference_change_mps) {
    LocalizerOptions options;
    options.slip_speed_difference_change_mps = slip_speed_difference_change_mps;
    std::unique_ptr<Localizer> localizer = Make(LocalizerMode::kOdometry, options);
    for (int k = 1; k <= 100; ++k) {
      core::WheelEncoderReading r = Straight(k);
      if (k == 51) r.left_delta_rad = -0.06 / kRadiusM;  // 1 cm forward less 7 cm spun back
      localizer->AddWheelReading(r);
    }
    return localizer;
  };
  const std::unique_ptr<Localizer> checked =
      drive(LocalizerOptions{}.slip_speed_difference_change_mps);
  EXPECT_EQ(checked->counters().wheel_dropped_slip, 1);
  EXPECT_EQ(checked->counters().wheel_coasted, 1);
  EXPECT_EQ(checked->counters().WheelReadingsDropped(), 1);
  EXPECT_NEAR(checked->Current().T_map_base.yaw(), 0.0, 1e-9);
  EXPECT_NEAR(checked->Current().T_map_base.x(), 1.00, 1e-9);
  const std::unique_ptr<Localizer> unchecked = drive(0.0);
  EXPECT_EQ(unchecked->counters().wheel_dropped_slip, 0);
  EXPECT_NEAR(unchecked->Current().T_map_base.yaw(), 0.07 / 0.76, 1e-6);

  // From a standstill to 1.8 m/s at 3 m/s^2, then braking at 5 m/s^2 to a
  // stop; and a localizer started while driving at 1.8 m/s.
  std::unique_ptr<Localizer> accelerating = Make(LocalizerMode::kOdometry);
  std::unique_ptr<Localizer> started_driving = Make(LocalizerMode::kOdometry);
  double speed_mps = 0.0;
  for (int k = 1; k <= 200; ++k) {
    speed_mps = k <= 60    ? std::min(1.8, speed_mps + 3.0 * kPeriodS)
                : k <= 100 ? std::max(0.0, speed_mps - 5.0 * kPeriodS)
                           : 0.0;
    const double delta_rad = speed_mps * kPeriodS / kRadiusM;
    accelerating->AddWheelReading({k * kPeriodS, delta_rad, delta_rad});
    const double driving_rad = 1.8 * kPeriodS / kRadiusM;
    started_driving->AddWheelReading({k * kPeriodS, driving_rad, driving_rad});
  }
  EXPECT_EQ(accelerating->counters().wheel_dropped_slip, 0);
  EXPECT_EQ(started_driving->counters().wheel_dropped_slip, 0);
  // Into a turn in place at 1 rad/s within 0.2 s (5 rad/s^2), and out again.
  std::unique_ptr<Localizer> turning = Make(LocalizerMode::kOdometry);
  double yaw_rate = 0.0;
  for (int k = 1; k <= 200; ++k) {
    yaw_rate = k <= 100 ? std::min(1.0, yaw_rate + 5.0 * kPeriodS)
                        : std::max(0.0, yaw_rate - 5.0 * kPeriodS);
    const double wheel_rad = yaw_rate * 0.5 * Vehicle().drive.track_m * kPeriodS / kRadiusM;
    turning->AddWheelReading({k * kPeriodS, -wheel_rad, wheel_rad});
  }
  EXPECT_EQ(turning->counters().wheel_dropped_slip, 0);
  EXPECT_NEAR(turning->Current().T_map_base.yaw(), 1.0, 0.02);
}

TEST(Localizer, OdometryIncrementsDriveItAsTheWheelReadingsTheyCameFrom) {
  // What a base driver publishes as nav_msgs/Odometry: the integrated wheel
  // poses; their consecutive Between are the increments.
  // The drive switches its wheel speeds at once (a step no vehicle makes,
  // which the slip check would drop): the check is off, this is about the
  // increments carrying what the readings do.
  LocalizerOptions no_slip_check;
  no_slip_check.slip_speed_difference_change_mps = 0.0;
  std::unique_ptr<Localizer> wheels = Make(LocalizerMode::kOdometry, no_slip_check);
  std::unique_ptr<Localizer> increments = Make(LocalizerMode::kOdometry, no_slip_check);
  OdometryIntegrator base_driver(Vehicle().drive, OdometryNoiseParams{});
  core::SE2 previous;
  std::vector<KeyframeOutput> from_wheels, from_increments;
  for (int k = 1; k <= 400; ++k) {
    // Straight, then a left arc, then turning in place to the right.
    const double l = k < 150 ? 0.08 : k < 300 ? 0.05 : 0.06;
    const double r = k < 150 ? 0.08 : k < 300 ? 0.09 : -0.06;
    const core::WheelEncoderReading reading{k * kPeriodS, l, r};
    base_driver.Integrate(WheelAngleIncrement{l, r});
    if (auto out = wheels->AddWheelReading(reading)) from_wheels.push_back(*out);
    const core::SE2 now = base_driver.T_odom_base();
    if (auto out = increments->AddOdometryIncrement(reading.stamp_s, previous.Between(now))) {
      from_increments.push_back(*out);
    }
    previous = now;
  }
  ASSERT_GT(from_wheels.size(), 10u);
  ASSERT_EQ(from_increments.size(), from_wheels.size());
  for (std::size_t i = 0; i < from_wheels.size(); ++i) {
    EXPECT_EQ(from_increments[i].stamp_s, from_wheels[i].stamp_s);
    EXPECT_TRUE(
        from_increments[i].pose.T_map_base.IsApprox(from_wheels[i].pose.T_map_base, 1e-9, 1e-9));
    EXPECT_TRUE(from_increments[i].pose.covariance.isApprox(from_wheels[i].pose.covariance, 1e-6));
  }
  EXPECT_TRUE(increments->Current().T_map_base.IsApprox(base_driver.T_odom_base(), 1e-9, 1e-9));
  // A non-finite increment is counted (and coasted over) as a non-finite reading.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  increments->AddOdometryIncrement(4.01, core::SE2(nan, 0.0, 0.0));
  EXPECT_EQ(increments->counters().wheel_dropped_non_finite, 1);
  EXPECT_EQ(increments->counters().wheel_coasted, 1);
}

TEST(Localizer, NonFiniteReadingsWithStampsAreCoastedOverUpToMaxCoastThenAreAGap) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::unique_ptr<Localizer> localizer = Make(LocalizerMode::kOdometry);
  for (int k = 1; k <= 100; ++k) localizer->AddWheelReading(Straight(k));
  for (int k = 101; k <= 150; ++k) localizer->AddWheelReading({k * kPeriodS, nan, nan});
  EXPECT_EQ(localizer->counters().wheel_dropped_non_finite, 50);
  EXPECT_EQ(localizer->counters().wheel_coasted, 50);
  EXPECT_DOUBLE_EQ(localizer->Current().stamp_s, 1.50);
  EXPECT_EQ(localizer->Sensors().degraded_mode, "none");  // nothing measures the motion
  for (int k = 151; k <= 300; ++k) localizer->AddWheelReading(Straight(k));
  EXPECT_TRUE(localizer->Sensors().odometry_ok);
  EXPECT_EQ(localizer->Sensors().degraded_mode, "full");
  EXPECT_NEAR(localizer->Current().T_map_base.x(), 3.0, 1e-9);

  // Longer than max_coast_s: the outputs stop there; the rest is a gap.
  LocalizerOptions options;
  options.mode = LocalizerMode::kOdometry;
  options.max_coast_s = 0.2;
  std::unique_ptr<Localizer> brief = std::move(Localizer::Create(options, Vehicle())).value();
  ASSERT_TRUE(brief->SetInitialPose(0.0, core::SE2(), StartCovariance()).ok());
  for (int k = 1; k <= 100; ++k) brief->AddWheelReading(Straight(k));
  for (int k = 101; k <= 200; ++k) brief->AddWheelReading({k * kPeriodS, nan, nan});
  EXPECT_EQ(brief->counters().wheel_coasted, 20);
  EXPECT_DOUBLE_EQ(brief->Current().stamp_s, 1.20);
  brief->AddWheelReading(Straight(201));
  EXPECT_EQ(brief->counters().odometry_gaps, 1);
}

TEST(Localizer, PoseAtInterpolatesTheOdometryRateHistory) {
  std::unique_ptr<Localizer> localizer = Make(LocalizerMode::kOdometry);
  for (int k = 1; k <= 100; ++k) localizer->AddWheelReading(Straight(k));
  const std::optional<PoseEstimate> mid = localizer->PoseAt(0.555);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->T_map_base.x(), 0.555, 1e-9);
  EXPECT_FALSE(localizer->PoseAt(1.5).has_value());   // after the newest reading
  EXPECT_FALSE(localizer->PoseAt(-1.0).has_value());  // before the start
  // The covariance grows along the drive.
  EXPECT_GT(localizer->Current().covariance(0, 0), localizer->PoseAt(0.1)->covariance(0, 0));
}

TEST(Localizer, FramesBeforeTheStartOrFarBehindTheOdometryAreDropped) {
  LocalizerOptions options;
  options.mode = LocalizerMode::kLines;
  std::unique_ptr<Localizer> localizer = std::move(Localizer::Create(options, Vehicle())).value();
  ConvertedObservations seen;
  seen.observations.stamp_s = -0.5;
  localizer->AddFloorObservations(seen);  // nobody knows where the vehicle is yet
  ASSERT_TRUE(localizer->SetInitialPose(0.0, core::SE2(), StartCovariance()).ok());
  for (int k = 1; k <= 100; ++k) localizer->AddWheelReading(Straight(k));
  seen.observations.stamp_s = 0.2;  // 0.8 s behind the newest reading (max 0.5 s)
  localizer->AddFloorObservations(seen);
  EXPECT_EQ(localizer->counters().frames_dropped_late, 2);
  EXPECT_EQ(localizer->counters().frames_used, 0);
}

// The 1.2 m circle in the room of lidar_test_world.h at 0.5 m/s.
core::SE2 CircleTruth(double t) {
  constexpr double kR = 1.2, kV = 0.5;
  const double a = kV * t / kR;
  return core::SE2(-0.5 + kR * std::sin(a), kR - kR * std::cos(a), a);
}

// A scan of the room stamped mid-sweep at stamp_s, 270 deg from -135 deg in
// steps of increment_rad, each ray cast from pose_at(its own time) as a 15 Hz
// sweeping scanner (one mirror revolution per scan) sees it.
core::LaserScan SweepScan(double stamp_s, double increment_rad,
                          const std::function<core::SE2(double)>& pose_at) {
  const std::vector<testing::Segment> walls = testing::RoomWorld();
  core::LaserScan scan;
  scan.stamp_s = stamp_s;
  scan.angle_min_rad = -0.75 * std::numbers::pi;
  scan.angle_increment_rad = increment_rad;
  scan.range_min_m = 0.05;
  scan.range_max_m = 20.0;
  const int rays = static_cast<int>(std::lround(1.5 * std::numbers::pi / increment_rad)) + 1;
  const double ray_s = increment_rad / (2.0 * std::numbers::pi * 15.0);
  const double first_ray_s = stamp_s - (rays - 1) * ray_s / 2.0;
  for (int i = 0; i < rays; ++i) {
    const core::SE2 T = pose_at(first_ray_s + i * ray_s);
    const double a = T.yaw() + scan.angle_min_rad + i * increment_rad;
    const double r = testing::CastRay(walls, T.translation(), {std::cos(a), std::sin(a)});
    scan.ranges_m.push_back(std::isfinite(r) && r < 20.0 ? r : 0.0);
  }
  return scan;
}

// Drives the circle for 20 s, the wheels over-reading by 2 %, the LiDAR at
// 15 Hz taking each scan at one instant (mid-sweep stamps; the localizers
// that take these scans do not deskew them); before_reading(t) runs before
// the reading at t.
// Returns the keyframes, each with the truth in the predicted pose's place.
std::vector<KeyframeOutput> DriveTheCircle(Localizer& localizer,
                                           const std::function<void(double)>& before_reading) {
  constexpr double kR = 1.2, kV = 0.5;
  std::vector<KeyframeOutput> keyframes;
  const double w = kV / kR, track = Vehicle().drive.track_m;
  int scan_k = 1;
  for (int k = 1; k <= 2000; ++k) {
    const double t = k * kPeriodS;
    while (scan_k / 15.0 <= t) {
      // Every ray from the scan's pose: a snapshot, nothing to deskew.
      localizer.AddScan(
          SweepScan(scan_k / 15.0, std::numbers::pi / 180.0,
                    [stamp_s = scan_k / 15.0](double) { return CircleTruth(stamp_s); }));
      ++scan_k;
    }
    if (before_reading) before_reading(t);
    const double left = 1.02 * (kV - w * track / 2.0) * kPeriodS / kRadiusM;
    const double right = 1.02 * (kV + w * track / 2.0) * kPeriodS / kRadiusM;
    if (auto out = localizer.AddWheelReading({t, left, right})) keyframes.push_back(*out);
  }
  for (KeyframeOutput& k : keyframes) k.predicted.T_map_base = CircleTruth(k.stamp_s);
  return keyframes;
}

LocalizerSetup VehicleWithLidar() {
  LocalizerSetup setup = Vehicle();
  setup.lidar = LidarSetup{core::SE2(), 15.0, core::LidarStamp::kMidSweep};
  return setup;
}

// kLidar around the circle; returns the keyframes.
std::vector<KeyframeOutput> CircleInTheRoom(int local_map_scans, LocalizerCounters* counters) {
  LocalizerOptions options;
  options.deskew_scans = false;  // DriveTheCircle's scans are snapshots
  options.mode = LocalizerMode::kLidar;
  options.lidar_local_map_scans = local_map_scans;
  std::unique_ptr<Localizer> localizer =
      std::move(Localizer::Create(options, VehicleWithLidar())).value();
  EXPECT_TRUE(localizer->SetInitialPose(0.0, CircleTruth(0.0), StartCovariance()).ok());
  std::vector<KeyframeOutput> keyframes = DriveTheCircle(*localizer, nullptr);
  *counters = localizer->counters();
  return keyframes;
}

TEST(Localizer, ARenewedScanOdometryContinuesFromItsEstimate) {
  LocalizerCounters once, renewed;
  const std::vector<KeyframeOutput> a = CircleInTheRoom(0, &once);
  const std::vector<KeyframeOutput> b = CircleInTheRoom(100, &renewed);  // every 6.7 s
  EXPECT_EQ(once.lidar_local_map_renewals, 0);
  EXPECT_GE(renewed.lidar_local_map_renewals, 2);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 30u);
  // The error of each keyframe, and its largest change between two keyframes.
  const auto errors = [](const std::vector<KeyframeOutput>& ks, double* worst, double* step) {
    *worst = *step = 0.0;
    double previous = 0.0;
    for (std::size_t i = 0; i < ks.size(); ++i) {
      const double e =
          (ks[i].pose.T_map_base.translation() - ks[i].predicted.T_map_base.translation()).norm();
      *worst = std::max(*worst, e);
      if (i > 0) *step = std::max(*step, std::abs(e - previous));
      previous = e;
    }
  };
  double worst_a, step_a, worst_b, step_b;
  errors(a, &worst_a, &step_a);
  errors(b, &worst_b, &step_b);
  // 2 % of the 10 m driven would be 20 cm for the wheels alone.
  EXPECT_LT(worst_a, 0.05);
  // No jump back to the wheels at a renewal (that would be 2 % of the 3.3 m
  // driven since the start: 6.7 cm); a fresh local map anchors where the
  // estimate is and matches less well for its first scans, so the drift may
  // grow a little after it.
  EXPECT_LT(step_b, step_a + 0.02) << "without renewals " << step_a << " m";
  EXPECT_LT(worst_b, 0.10);
}

// A turn in the room at 0.8 m/s: 2 s straight, the yaw rate ramping to
// 0.6 rad/s in 0.4 s, held 2.3 s, ramping down, then straight (93 deg in
// all), with scans of a 15 Hz sweeping scanner (SweepScan); the wheels read
// the truth's increments. Returns the largest change of the kLidar
// estimate's heading error from the turn's start, in degrees.
double HeadingErrorChangeOverATurn(bool deskew) {
  constexpr double kV = 0.8, kStepS = 0.001, kTurnS = 2.0, kEndS = 7.0;
  const auto yaw_rate = [](double t) {
    if (t < kTurnS || t > 5.1) return 0.0;
    if (t < 2.4) return 0.6 * (t - kTurnS) / 0.4;
    if (t > 4.7) return 0.6 * (5.1 - t) / 0.4;
    return 0.6;
  };
  core::Trajectory truth{{0.0, core::SE2(-3.0, -1.0, 0.0), std::nullopt}};
  for (double t = kStepS; t <= kEndS + 0.2; t += kStepS) {
    const core::SE2& last = truth.back().pose;
    const double yaw = last.yaw() + yaw_rate(t - kStepS / 2.0) * kStepS;
    const double mid = 0.5 * (last.yaw() + yaw);
    truth.push_back({t,
                     core::SE2(last.x() + kV * kStepS * std::cos(mid),
                               last.y() + kV * kStepS * std::sin(mid), yaw),
                     std::nullopt});
  }
  const auto pose_at = [&truth](double t) { return core::InterpolatePose(truth, t); };
  LocalizerOptions options;
  options.mode = LocalizerMode::kLidar;
  options.deskew_scans = deskew;
  std::unique_ptr<Localizer> localizer =
      std::move(Localizer::Create(options, VehicleWithLidar())).value();
  EXPECT_TRUE(localizer->SetInitialPose(0.0, truth.front().pose, StartCovariance()).ok());
  const double track = Vehicle().drive.track_m;
  std::optional<double> at_turn;
  double worst = 0.0;
  int scan_k = 1;
  for (int k = 1; k * kPeriodS <= kEndS; ++k) {
    const double t = k * kPeriodS;
    while (scan_k / 15.0 <= t) {
      localizer->AddScan(SweepScan(scan_k / 15.0, 0.33 * std::numbers::pi / 180.0, pose_at));
      ++scan_k;
    }
    const core::SE2 delta = pose_at(t - kPeriodS).Inverse() * pose_at(t);
    const double ds = delta.translation().norm(), dyaw = delta.yaw();
    const double left = (ds - dyaw * track / 2.0) / kRadiusM;
    const double right = (ds + dyaw * track / 2.0) / kRadiusM;
    const std::optional<KeyframeOutput> out = localizer->AddWheelReading({t, left, right});
    if (!out) continue;
    const double error = core::WrapAngle(out->pose.T_map_base.yaw() - pose_at(out->stamp_s).yaw());
    if (out->stamp_s <= kTurnS) {
      at_turn = error;  // the last keyframe before the turn
    } else if (at_turn) {
      worst = std::max(worst, std::abs(error - *at_turn));
    }
  }
  EXPECT_TRUE(at_turn.has_value());
  return worst * 180.0 / std::numbers::pi;
}

TEST(Localizer, ScansTakenWhileTheYawRateRampsAreDeskewedBeforeTheyAreMatched) {
  const double deskewed = HeadingErrorChangeOverATurn(true);
  const double not_deskewed = HeadingErrorChangeOverATurn(false);
  // A sweep spans 1.7 deg of heading at 0.6 rad/s. Undeskewed, the turn's
  // scans are bent against the local map of the straight before it (the
  // check that the drive shows the effect).
  EXPECT_LT(deskewed, 0.08) << "without deskewing " << not_deskewed << " deg";
  EXPECT_GT(not_deskewed, 0.15);
}

TEST(Localizer, AReinitializationMovesTheDeadReckoningWithItsCovarianceAndKeepsTheOdomFrame) {
  std::unique_ptr<Localizer> localizer = Make(LocalizerMode::kOdometry);
  for (int k = 1; k <= 100; ++k) localizer->AddWheelReading(Straight(k));
  // The pose 50 ms before the newest reading (1.00 s), facing +y.
  const core::Matrix3 given = core::Vector3(1e-4, 4e-4, 1e-6).asDiagonal();
  ASSERT_TRUE(
      localizer->SetInitialPose(0.95, core::SE2(5.0, -1.0, std::numbers::pi / 2), given).ok());
  const PoseEstimate now = localizer->Current();
  EXPECT_DOUBLE_EQ(now.stamp_s, 1.0);
  EXPECT_TRUE(now.T_map_base.IsApprox(core::SE2(5.0, -0.95, std::numbers::pi / 2), 1e-9, 1e-9));
  // Carried 5 cm straight ahead (tangent space at the pose, right
  // perturbation): the given covariance, plus the yaw's lever arm on y, plus
  // the odometry's own noise over the 5 cm.
  EXPECT_GT(now.covariance(0, 0), given(0, 0));
  EXPECT_LT(now.covariance(0, 0), given(0, 0) + 1e-5);
  EXPECT_GT(now.covariance(1, 1), given(1, 1) + 0.05 * 0.05 * given(2, 2));
  EXPECT_LT(now.covariance(1, 1), given(1, 1) + 1e-5);
  std::vector<KeyframeOutput> keyframes;
  for (int k = 101; k <= 200; ++k) {
    if (auto out = localizer->AddWheelReading(Straight(k))) keyframes.push_back(*out);
  }
  ASSERT_FALSE(keyframes.empty());
  for (const KeyframeOutput& k : keyframes) EXPECT_NEAR(k.pose.T_map_base.x(), 5.0, 1e-9);
  EXPECT_TRUE(localizer->Current().T_map_base.IsApprox(core::SE2(5.0, 0.05, std::numbers::pi / 2),
                                                       1e-9, 1e-9));
  EXPECT_GT(localizer->Current().covariance(0, 0), now.covariance(0, 0));
  // Before the re-initialization: not carried across it.
  EXPECT_FALSE(localizer->SetInitialPose(0.97, core::SE2(), given).ok());
  const LocalizerCounters& c = localizer->counters();
  EXPECT_EQ(c.reinitializations, 1);
  EXPECT_EQ(c.initial_poses_dropped_late, 1);
}

// Translation errors against the truth (in the predicted pose's place,
// DriveTheCircle) of the keyframes stamped in [from_s, to_s): the smallest
// and the largest [m].
std::pair<double, double> ErrorRange(const std::vector<KeyframeOutput>& ks, double from_s,
                                     double to_s) {
  double least = std::numeric_limits<double>::infinity(), most = 0.0;
  for (const KeyframeOutput& k : ks) {
    if (k.stamp_s < from_s || k.stamp_s >= to_s) continue;
    const double e =
        (k.pose.T_map_base.translation() - k.predicted.T_map_base.translation()).norm();
    least = std::min(least, e);
    most = std::max(most, e);
  }
  return {least, most};
}

// Started 1.5 m and 10 deg off, the vehicle is put back on its true pose at
// 8 s (RViz's "2D Pose Estimate"). Poses far ahead of the odometry or older
// than its history are dropped and counted first, moving nothing.
TEST(Localizer, AReinitializationMidRunContinuesTheLidarEstimateFromTheGivenPose) {
  LocalizerOptions options;
  options.deskew_scans = false;  // DriveTheCircle's scans are snapshots
  options.mode = LocalizerMode::kLidar;
  std::unique_ptr<Localizer> localizer =
      std::move(Localizer::Create(options, VehicleWithLidar())).value();
  const core::SE2 start_error(1.5, 0.0, 10.0 * std::numbers::pi / 180.0);
  ASSERT_TRUE(
      localizer->SetInitialPose(0.0, CircleTruth(0.0) * start_error, StartCovariance()).ok());
  const core::Matrix3 given = core::Vector3(1e-4, 1e-4, 1e-4).asDiagonal();
  std::optional<PoseEstimate> after;
  const std::vector<KeyframeOutput> keyframes = DriveTheCircle(*localizer, [&](double t) {
    if (std::abs(t - 8.0) > 1e-6) return;  // the newest reading is at 7.99 s
    const PoseEstimate before = localizer->Current();
    EXPECT_FALSE(localizer->SetInitialPose(t + 10.0, CircleTruth(t), given).ok());
    EXPECT_FALSE(localizer->SetInitialPose(t - 5.0, CircleTruth(t - 5.0), given).ok());
    EXPECT_TRUE(localizer->Current().T_map_base.IsApprox(before.T_map_base));
    // The true pose at 7.95 s (a click 40 ms old), carried to 7.99 s by the wheels.
    ASSERT_TRUE(localizer->SetInitialPose(7.95, CircleTruth(7.95), given).ok());
    after = localizer->Current();
  });
  ASSERT_TRUE(after.has_value());
  const LocalizerCounters& c = localizer->counters();
  EXPECT_EQ(c.reinitializations, 1);
  EXPECT_EQ(c.initial_poses_dropped_ahead, 1);
  EXPECT_EQ(c.initial_poses_dropped_late, 1);
  // 2 cm of wheel travel over-read by 2 %: 0.4 mm.
  EXPECT_NEAR(after->stamp_s, 7.99, 1e-9);
  EXPECT_LT((after->T_map_base.translation() - CircleTruth(7.99).translation()).norm(), 0.002);
  const auto [least_before, most_before] = ErrorRange(keyframes, 0.0, 8.0);
  const auto [least_after, most_after] = ErrorRange(keyframes, 8.0, 21.0);
  const double most_first = ErrorRange(keyframes, 8.0, 8.5).second;
  std::printf("keyframe error before %.3f..%.3f m, after %.4f..%.4f m (first 0.5 s %.4f m)\n",
              least_before, most_before, least_after, most_after, most_first);
  EXPECT_GT(least_before, 1.0);
  // The renewed scan odometry continues from the given pose, with no pull
  // back to the old one (1.0-1.5 m). Without a map nothing but the given
  // pose anchors it: what remains is a fresh local map's own error (its
  // first scans match less well: 2 cm at the start of this drive, 4-6 cm
  // after the re-initialization, near the shelf).
  EXPECT_LT(most_first, 0.08);
  EXPECT_LT(most_after, 0.08);
  EXPECT_LT(
      (localizer->Current().T_map_base.translation() - CircleTruth(20.0).translation()).norm(),
      0.08);
}

// The smoother's path (kLines on the room's walls, the LiDAR alone): a
// re-initialization stamped just ahead of the odometry is held until a
// reading reaches it (a newer one replaces a held one), then the window
// restarts there and the walls hold the estimate at the given pose.
TEST(Localizer, AReinitializationAheadOfTheOdometryRestartsTheSmootherAtItsStamp) {
  LocalizerOptions options;
  options.deskew_scans = false;  // DriveTheCircle's scans are snapshots
  options.mode = LocalizerMode::kLines;
  options.use_lidar = true;
  LocalizerSetup setup = VehicleWithLidar();
  std::vector<WallSegment> segments;
  for (const testing::Segment& s : testing::RoomWorld()) segments.push_back({s.a, s.b, false});
  ASSERT_TRUE(AppendWallLines(segments, AtlasWallOptions(), &setup.atlas).ok());
  std::unique_ptr<Localizer> localizer =
      std::move(Localizer::Create(options, std::move(setup))).value();
  const core::SE2 start_error(1.5, 0.0, 10.0 * std::numbers::pi / 180.0);
  ASSERT_TRUE(
      localizer->SetInitialPose(0.0, CircleTruth(0.0) * start_error, StartCovariance()).ok());
  const core::Matrix3 given = core::Vector3(1e-4, 1e-4, 1e-4).asDiagonal();
  std::optional<PoseEstimate> held, applied;
  const std::vector<KeyframeOutput> keyframes = DriveTheCircle(*localizer, [&](double t) {
    if (std::abs(t - 8.0) < 1e-6) {
      // 13 and 15 ms after the newest reading (7.99 s): held, the second wins.
      const core::SE2 wrong = CircleTruth(8.003) * start_error;
      ASSERT_TRUE(localizer->SetInitialPose(8.003, wrong, given).ok());
      ASSERT_TRUE(localizer->SetInitialPose(8.005, CircleTruth(8.005), given).ok());
      held = localizer->Current();
    } else if (std::abs(t - 8.02) < 1e-6) {
      applied = localizer->Current();  // at 8.01 s
    }
  });
  ASSERT_TRUE(held && applied);
  const LocalizerCounters& c = localizer->counters();
  EXPECT_EQ(c.reinitializations, 1);
  EXPECT_EQ(c.initial_poses_superseded, 1);
  EXPECT_GT(c.walls_used, 0);
  EXPECT_GT((held->T_map_base.translation() - CircleTruth(7.99).translation()).norm(), 0.5);
  EXPECT_NEAR(applied->stamp_s, 8.01, 1e-9);
  EXPECT_LT((applied->T_map_base.translation() - CircleTruth(8.01).translation()).norm(), 0.002);
  const auto [least_before, most_before] = ErrorRange(keyframes, 0.0, 8.0);
  const auto [least_after, most_after] = ErrorRange(keyframes, 8.0, 21.0);
  std::printf("keyframe error before %.3f..%.3f m, after %.4f..%.4f m\n", least_before, most_before,
              least_after, most_after);
  EXPECT_LT(most_after, 0.02);
  EXPECT_LT(
      (localizer->Current().T_map_base.translation() - CircleTruth(20.0).translation()).norm(),
      0.02);
}

TEST(Localizer, RefusesWhatItsSetupCannotDo) {
  LocalizerOptions options;
  options.mode = LocalizerMode::kLidar;  // no LiDAR in the setup
  core::Result<std::unique_ptr<Localizer>> lidar = Localizer::Create(options, Vehicle());
  ASSERT_FALSE(lidar.ok());
  EXPECT_NE(lidar.message().find("LiDAR"), std::string::npos) << lidar.message();

  options.mode = LocalizerMode::kOdometry;
  options.blind_keyframe_m = std::numeric_limits<double>::quiet_NaN();
  core::Result<std::unique_ptr<Localizer>> invalid = Localizer::Create(options, Vehicle());
  ASSERT_FALSE(invalid.ok());
  EXPECT_NE(invalid.message().find("blind_keyframe_m"), std::string::npos) << invalid.message();

  options = LocalizerOptions();
  options.mode = LocalizerMode::kOdometry;
  std::unique_ptr<Localizer> odometry = std::move(Localizer::Create(options, Vehicle())).value();
  EXPECT_FALSE(odometry->RequestRelocalization().ok());  // nothing to recognize
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(odometry->SetInitialPose(0.0, core::SE2(1.0, 2.0, nan), StartCovariance()).ok());
  EXPECT_FALSE(odometry->SetInitialPose(0.0, core::SE2(), -StartCovariance()).ok());
  EXPECT_FALSE(odometry->started());
  // Readings before a start are counted, not integrated.
  odometry->AddWheelReading(Straight(1));
  EXPECT_EQ(odometry->counters().wheel_before_start, 1);
}

}  // namespace
}  // namespace groundline::localization
