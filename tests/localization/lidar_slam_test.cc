// LidarSlam on exact ray-cast scans of a hand-built room: the log's wheel
// odometry is stale while the robot turns in place (it reports no motion
// for several scans, then the whole turn at once), as on the MIT CSAIL log.
// The front end follows the turn from the scans; the pose graph must keep
// it (a stale odometry increment is not a measurement of "no motion").
// With a calibrated vehicle's gate on the match's correction
// (max_match_correction_*), a correction beyond it is not used unless the
// following scans repeat it.
#include "groundline/localization/lidar/lidar_slam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "lidar_test_world.h"
#include "test_units.h"

namespace groundline::localization::lidar {
namespace {

using ::groundline::testing::kDeg;

TEST(LidarSlam, StaleOdometryDuringATurnInPlaceDoesNotBendTheGraph) {
  const auto walls = testing::RoomWorld();
  // Drive 0.4 m along x, turn 120 degrees in place at 10 degrees per scan,
  // drive 0.4 m on; 0.2 s per scan.
  std::vector<core::SE2> truth;
  core::SE2 pose(-2.0, -0.5, 0.0);
  for (int i = 0; i < 4; ++i) truth.push_back(pose = pose * core::SE2(0.1, 0.0, 0.0));
  for (int i = 0; i < 12; ++i) truth.push_back(pose = pose * core::SE2(0.0, 0.0, 10.0 * kDeg));
  for (int i = 0; i < 4; ++i) truth.push_back(pose = pose * core::SE2(0.1, 0.0, 0.0));
  LidarSlamOptions options;
  options.scans_per_submap = 4;  // several submaps and finished ones
  // The velocity hypothesis covers the stale odometry; a narrower window
  // than the default keeps the test fast under the sanitizers.
  options.matcher.angular_window_rad = 0.2;
  options.matcher.max_search_points = 60;
  options.loop_search = {0.5, 0.2, 5, 80};
  LidarSlam slam(options);
  core::SE2 T_odom_base;  // odometry frame = world frame
  for (std::size_t i = 0; i < truth.size(); ++i) {
    // Stale: the odometry holds its value for 4 of every 5 scans during
    // the turn, then jumps to the truth.
    const bool turning = i >= 4 && i < 16;
    if (!turning || i % 5 == 0) T_odom_base = truth[i];
    const ScanPoints scan = testing::SimulateScan(walls, truth[i], 0.01, 300 + i);
    core::Result<ScanReport> report = slam.AddScan(0.2 * static_cast<double>(i), T_odom_base, scan);
    ASSERT_TRUE(report.ok()) << report.message();
  }
  ASSERT_TRUE(slam.Finish().ok());
  const core::Trajectory trajectory = slam.Trajectory();
  ASSERT_EQ(trajectory.size(), truth.size());
  // The map frame is the first scan's pose.
  const core::SE2 T_world_map = truth.front();
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const core::SE2 error = truth[i].Between(T_world_map * trajectory[i].pose);
    EXPECT_LT(error.translation().norm(), 0.05) << "scan " << i;
    EXPECT_LT(std::abs(error.yaw()), 0.5 * kDeg) << "scan " << i;
  }
}

// Drives 0.1 m per scan along x in the room; at scan `jump` the odometry
// turns by `odometry_jump_rad` that the scans do not show (and keeps it).
// Returns each scan's report.
struct GateRun {
  std::vector<ScanReport> reports;
};
GateRun DriveWithAnOdometryJump(const LidarSlamOptions& options, int jump,
                                double odometry_jump_rad) {
  const auto walls = testing::RoomWorld();
  LidarSlam slam(options);
  GateRun run;
  core::SE2 truth(-2.0, -0.5, 0.0);
  for (int i = 0; i < 8; ++i) {
    if (i > 0) truth = truth * core::SE2(0.1, 0.0, 0.0);
    const core::SE2 T_odom_base =
        i >= jump ? truth * core::SE2(0.0, 0.0, odometry_jump_rad) : truth;
    const ScanPoints scan = testing::SimulateScan(walls, truth, 0.01, 400 + i);
    core::Result<ScanReport> report = slam.AddScan(0.1 * i, T_odom_base, scan);
    EXPECT_TRUE(report.ok()) << report.message();
    if (report.ok()) run.reports.push_back(*report);
  }
  return run;
}

TEST(LidarSlam, AMatchThatCorrectsTheOdometryBeyondTheGateIsNotUsed) {
  LidarSlamOptions options;
  options.matcher.max_search_points = 60;
  constexpr int kJump = 4;
  const double jump_rad = 4.0 * kDeg;
  // No gate: the scans turn the front end back onto the truth.
  const GateRun ungated = DriveWithAnOdometryJump(options, kJump, jump_rad);
  ASSERT_EQ(ungated.reports.size(), 8u);
  EXPECT_TRUE(ungated.reports[kJump].matched);
  EXPECT_FALSE(ungated.reports[kJump].match_gated);
  EXPECT_LT(std::abs(ungated.reports[kJump].T_local_base.yaw()), 0.3 * kDeg);
  // A gate of 3 deg: the 4 deg correction is not used, the odometry's
  // prediction is kept, until the third scan in a row asks for the same
  // correction (the wheels' error, not the scans'): that one is used.
  options.max_match_correction_m = 0.1;
  options.max_match_correction_rad = 3.0 * kDeg;
  options.match_correction_persist_scans = 3;
  const GateRun gated = DriveWithAnOdometryJump(options, kJump, jump_rad);
  ASSERT_EQ(gated.reports.size(), 8u);
  for (int i = 1; i < kJump; ++i) EXPECT_TRUE(gated.reports[i].matched) << "scan " << i;
  for (int i = kJump; i < kJump + 2; ++i) {
    EXPECT_FALSE(gated.reports[i].matched) << "scan " << i;
    EXPECT_TRUE(gated.reports[i].match_gated) << "scan " << i;
    EXPECT_NEAR(gated.reports[i].T_local_base.yaw(), jump_rad, 0.3 * kDeg) << "scan " << i;
  }
  for (int i = kJump + 2; i < 8; ++i) {
    EXPECT_TRUE(gated.reports[i].matched) << "scan " << i;
    EXPECT_FALSE(gated.reports[i].match_gated) << "scan " << i;
    EXPECT_LT(std::abs(gated.reports[i].T_local_base.yaw()), 0.3 * kDeg) << "scan " << i;
  }
}

}  // namespace
}  // namespace groundline::localization::lidar
