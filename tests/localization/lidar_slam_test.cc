// LidarSlam on exact ray-cast scans of a hand-built room: the log's wheel
// odometry is stale while the robot turns in place (it reports no motion
// for several scans, then the whole turn at once), as on the MIT CSAIL log.
// The front end follows the turn from the scans; the pose graph must keep
// it (a stale odometry increment is not a measurement of "no motion").
#include "groundline/localization/lidar/lidar_slam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

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

}  // namespace
}  // namespace groundline::localization::lidar
