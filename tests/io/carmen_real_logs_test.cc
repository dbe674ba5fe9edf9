// CARMEN parsing of the three real logs in ../shared/data/lidar2d.
//
// The expected counts and field values were obtained independently of this
// reader, from the file text with bzcat | awk / sed (e.g.
// `bzcat aces.clf.bz2 | awk '{print $1}' | sort | uniq -c`, and
// `awk '$1=="FLASER"{print $2}'` for the readings per scan).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "groundline/io/carmen.h"
#include "groundline/io/carmen_trajectory.h"
#include "test_data.h"
#include "test_units.h"

namespace groundline::io {
namespace {

using groundline::testing::SharedDataDir;

using ::groundline::testing::kPi;
// Values are written with 2-6 decimals; parsed doubles must match exactly up
// to the decimal-to-binary rounding.
constexpr double kParseTol = 1e-9;

CarmenLog ReadStrict(const std::string& name) {
  CarmenReadOptions options;
  options.strict = true;
  core::Result<CarmenLog> log = ReadCarmenLog(SharedDataDir() / "lidar2d" / name, options);
  EXPECT_TRUE(log.ok()) << log.message();
  return log.ok() ? std::move(log).value() : CarmenLog{};
}

void ExpectPose(const core::SE2& pose, double x, double y, double theta) {
  EXPECT_NEAR(pose.x(), x, kParseTol);
  EXPECT_NEAR(pose.y(), y, kParseTol);
  EXPECT_NEAR(pose.yaw(), theta, kParseTol);
}

// Laser stamps strictly increase in all three logs (checked with awk).
void ExpectScanStampsStrictlyIncrease(const CarmenLog& log) {
  for (std::size_t i = 1; i < log.scans.size(); ++i) {
    ASSERT_GT(log.scans[i].stamp_s, log.scans[i - 1].stamp_s) << "scan " << i;
  }
}

TEST(CarmenRealLogs, Aces) {
  GROUNDLINE_REQUIRE_DATA("lidar2d/aces.clf.bz2");
  const CarmenLog log = ReadStrict("aces.clf.bz2");
  const CarmenReadSummary& s = log.summary;
  EXPECT_EQ(s.lines, 14762);
  EXPECT_EQ(s.comment_lines, 9);
  EXPECT_EQ(s.blank_lines, 0);
  EXPECT_EQ(s.Count("PARAM"), 4);
  EXPECT_EQ(s.Count("ODOM"), 7375);
  EXPECT_EQ(s.Count("FLASER"), 7374);
  EXPECT_EQ(s.message_counts.size(), 3u);
  EXPECT_EQ(s.unknown_messages, 0);
  EXPECT_EQ(s.skipped_line_count, 0);
  ASSERT_EQ(log.odometry.size(), 7375u);
  ASSERT_EQ(log.scans.size(), 7374u);
  EXPECT_TRUE(log.true_poses.empty());

  // Old-style PARAM lines without ipc_timestamp: "PARAM robot_use_laser on nohost 0".
  ASSERT_EQ(log.params.size(), 4u);
  EXPECT_EQ(log.params.at("robot_use_laser"), "on");
  EXPECT_EQ(log.params.at("simulator_num_readings"), "180");
  EXPECT_EQ(log.params.at("robot_frontlaser_offset"), "0.0");
  EXPECT_EQ(log.params.at("robot_rearlaser_offset"), "0.0");

  // Line 14: ODOM -0.000602 0.012727 -1.570796 0.000000 0.000000 0.000000 70.179699 nohost 0.000000
  const CarmenOdometry& first_odom = log.odometry.front();
  EXPECT_EQ(first_odom.line, 14);
  ExpectPose(first_odom.pose, -0.000602, 0.012727, -1.570796);
  EXPECT_EQ(first_odom.tv_mps, 0.0);
  EXPECT_NEAR(first_odom.stamp_s, 70.179699, kParseTol);
  EXPECT_EQ(first_odom.logger_stamp_s, 0.0);
  // Line 14762: ODOM -17.805700 -3.180960 2.478771 0 0 0 1435.900000 nohost 1365.720301
  const CarmenOdometry& last_odom = log.odometry.back();
  EXPECT_EQ(last_odom.line, 14762);
  ExpectPose(last_odom.pose, -17.805700, -3.180960, 2.478771);
  EXPECT_NEAR(last_odom.stamp_s, 1435.9, kParseTol);
  EXPECT_NEAR(last_odom.logger_stamp_s, 1365.720301, kParseTol);

  // Line 15: FLASER 180 46.56 47.31 12.51 ... 6.36 <pose> <pose> 70.289900 nohost 0.110201
  const CarmenLaserScan& first = log.scans.front();
  EXPECT_EQ(first.line, 15);
  EXPECT_EQ(first.message, CarmenLaserMessage::kFlaser);
  EXPECT_EQ(first.laser_id, 1);
  ASSERT_EQ(first.ranges_m.size(), 180u);
  EXPECT_NEAR(first.ranges_m[0], 46.56, kParseTol);
  EXPECT_NEAR(first.ranges_m[1], 47.31, kParseTol);
  EXPECT_NEAR(first.ranges_m[2], 12.51, kParseTol);
  EXPECT_NEAR(first.ranges_m[179], 6.36, kParseTol);
  EXPECT_TRUE(first.remissions.empty());
  ASSERT_TRUE(first.laser_pose.has_value() && first.robot_pose.has_value());
  ExpectPose(*first.laser_pose, -0.000602, 0.012727, -1.570796);
  ExpectPose(*first.robot_pose, -0.000602, 0.012727, -1.570796);
  EXPECT_NEAR(first.stamp_s, 70.2899, kParseTol);
  EXPECT_NEAR(first.logger_stamp_s, 0.110201, kParseTol);
  // CARMEN's old-format geometry for 180 readings: -90 deg, 1 deg steps.
  EXPECT_DOUBLE_EQ(first.angle_min_rad, -kPi / 2);
  EXPECT_DOUBLE_EQ(first.angle_increment_rad, kPi / 180);
  EXPECT_DOUBLE_EQ(first.BeamAngleRad(179), kPi / 2 - kPi / 180);
  EXPECT_DOUBLE_EQ(first.max_range_m, 80.0);

  // Line 14761: FLASER 180 1.52 1.52 1.57 ... 1.02 <pose> <pose> 1435.809999 nohost 1365.630300
  const CarmenLaserScan& last = log.scans.back();
  EXPECT_EQ(last.line, 14761);
  EXPECT_NEAR(last.ranges_m[0], 1.52, kParseTol);
  EXPECT_NEAR(last.ranges_m[2], 1.57, kParseTol);
  EXPECT_NEAR(last.ranges_m[179], 1.02, kParseTol);
  ExpectPose(*last.robot_pose, -17.805700, -3.180960, 2.478771);
  EXPECT_NEAR(last.stamp_s, 1435.809999, kParseTol);
  EXPECT_NEAR(last.logger_stamp_s, 1365.6303, kParseTol);

  for (const CarmenLaserScan& scan : log.scans) ASSERT_EQ(scan.ranges_m.size(), 180u);
  ExpectScanStampsStrictlyIncrease(log);
  // ODOM stamps never decrease; awk finds exactly one repeat (line 14032).
  int repeats = 0;
  for (std::size_t i = 1; i < log.odometry.size(); ++i) {
    ASSERT_GE(log.odometry[i].stamp_s, log.odometry[i - 1].stamp_s);
    if (log.odometry[i].stamp_s == log.odometry[i - 1].stamp_s) {
      ++repeats;
      EXPECT_EQ(log.odometry[i].line, 14032);
    }
  }
  EXPECT_EQ(repeats, 1);

  core::Result<core::Trajectory> trajectory = CarmenScanTrajectory(log);
  ASSERT_TRUE(trajectory.ok()) << trajectory.message();
  ASSERT_EQ(trajectory->size(), 7374u);
  EXPECT_EQ(trajectory->front().stamp_s, first.stamp_s);
  ExpectPose(trajectory->back().pose, -17.805700, -3.180960, 2.478771);
}

TEST(CarmenRealLogs, MitCsail) {
  GROUNDLINE_REQUIRE_DATA("lidar2d/mit-csail.clf.bz2");
  const CarmenLog log = ReadStrict("mit-csail.clf.bz2");
  const CarmenReadSummary& s = log.summary;
  EXPECT_EQ(s.lines, 1991);
  EXPECT_EQ(s.comment_lines, 3);
  EXPECT_EQ(s.Count("FLASER"), 1988);
  EXPECT_EQ(s.message_counts.size(), 1u);
  EXPECT_EQ(s.skipped_line_count, 0);
  EXPECT_TRUE(log.odometry.empty());  // odometry only inside the FLASER lines
  ASSERT_EQ(log.scans.size(), 1988u);

  // Line 4: FLASER 361 1.40 1.39 1.39 ... 2.70 576.536523 0.106594 -2.255213 (twice)
  //         1134864629.895182 b21 0.086295
  const CarmenLaserScan& first = log.scans.front();
  EXPECT_EQ(first.line, 4);
  ASSERT_EQ(first.ranges_m.size(), 361u);
  EXPECT_NEAR(first.ranges_m[0], 1.40, kParseTol);
  EXPECT_NEAR(first.ranges_m[1], 1.39, kParseTol);
  EXPECT_NEAR(first.ranges_m[360], 2.70, kParseTol);
  ExpectPose(*first.laser_pose, 576.536523, 0.106594, -2.255213);
  ExpectPose(*first.robot_pose, 576.536523, 0.106594, -2.255213);
  // Absolute Unix time: 1e-6 is the resolution a double keeps at 1.1e9 s.
  EXPECT_NEAR(first.stamp_s, 1134864629.895182, 1e-6);
  EXPECT_NEAR(first.logger_stamp_s, 0.086295, kParseTol);
  // 361 readings: 0.5 deg steps over 180 deg from -90 deg.
  EXPECT_DOUBLE_EQ(first.angle_increment_rad, kPi / 360);
  EXPECT_NEAR(first.BeamAngleRad(360), kPi / 2, 1e-12);

  // Line 1991: FLASER 361 3.98 3.97 3.34 ... 2.21 597.816512 -3.220376 -1.412351 (twice)
  //            1134865053.892206 b21 424.077432
  const CarmenLaserScan& last = log.scans.back();
  EXPECT_EQ(last.line, 1991);
  EXPECT_NEAR(last.ranges_m[0], 3.98, kParseTol);
  EXPECT_NEAR(last.ranges_m[360], 2.21, kParseTol);
  ExpectPose(*last.robot_pose, 597.816512, -3.220376, -1.412351);
  EXPECT_NEAR(last.stamp_s, 1134865053.892206, 1e-6);
  EXPECT_NEAR(last.logger_stamp_s, 424.077432, kParseTol);

  for (const CarmenLaserScan& scan : log.scans) ASSERT_EQ(scan.ranges_m.size(), 361u);
  ExpectScanStampsStrictlyIncrease(log);
  core::Result<core::Trajectory> trajectory = CarmenScanTrajectory(log);
  ASSERT_TRUE(trajectory.ok()) << trajectory.message();
  EXPECT_EQ(trajectory->size(), 1988u);
}

TEST(CarmenRealLogs, FreiburgClinicRobotLaser) {
  GROUNDLINE_REQUIRE_DATA("lidar2d/fr-clinic_robotlaser.clf.bz2");
  const CarmenLog log = ReadStrict("fr-clinic_robotlaser.clf.bz2");
  const CarmenReadSummary& s = log.summary;
  EXPECT_EQ(s.lines, 6917);
  EXPECT_EQ(s.comment_lines, 0);
  EXPECT_EQ(s.Count("ROBOTLASER1"), 6917);
  EXPECT_EQ(s.message_counts.size(), 1u);
  EXPECT_EQ(s.skipped_line_count, 0);
  ASSERT_EQ(log.scans.size(), 6917u);

  // Line 1: ROBOTLASER1 0 -1.570796 3.141593 0.017453 81.900000 0.010000 0 181
  //   14.120 7.160 49.610 ... 15.880 0 0.220000 0 0 0 0 0 0 0 0 0 0
  //   1232658478.161285 zoidberg2 -0.055208
  const CarmenLaserScan& first = log.scans.front();
  EXPECT_EQ(first.message, CarmenLaserMessage::kRobotLaser);
  EXPECT_EQ(first.laser_id, 1);
  EXPECT_EQ(CarmenLaserMessageName(first), "ROBOTLASER1");
  EXPECT_EQ(first.laser_type, 0);
  EXPECT_NEAR(first.angle_min_rad, -1.570796, kParseTol);
  EXPECT_NEAR(first.angle_increment_rad, 0.017453, kParseTol);
  EXPECT_NEAR(first.max_range_m, 81.9, kParseTol);
  ASSERT_EQ(first.ranges_m.size(), 181u);
  EXPECT_NEAR(first.ranges_m[0], 14.12, kParseTol);
  EXPECT_NEAR(first.ranges_m[1], 7.16, kParseTol);
  EXPECT_NEAR(first.ranges_m[2], 49.61, kParseTol);
  EXPECT_NEAR(first.ranges_m[180], 15.88, kParseTol);
  EXPECT_TRUE(first.remissions.empty());
  ExpectPose(*first.laser_pose, 0.22, 0.0, 0.0);
  ExpectPose(*first.robot_pose, 0.0, 0.0, 0.0);
  EXPECT_EQ(first.tv_mps, 0.0);
  EXPECT_NEAR(first.stamp_s, 1232658478.161285, 1e-6);
  EXPECT_NEAR(first.logger_stamp_s, -0.055208, kParseTol);

  // Line 6917: ... -1.566433 ... 180 8.450 9.390 81.910 ... 8.540 0
  //   2.289982 -10.869829 0.207979 2.074723 -10.915255 0.207979 0 0 0 0 0
  //   1232663298.321285 zoidberg2 4820.104792
  const CarmenLaserScan& last = log.scans.back();
  EXPECT_EQ(last.line, 6917);
  EXPECT_NEAR(last.angle_min_rad, -1.566433, kParseTol);
  ASSERT_EQ(last.ranges_m.size(), 180u);
  EXPECT_NEAR(last.ranges_m[0], 8.45, kParseTol);
  EXPECT_NEAR(last.ranges_m[2], 81.91, kParseTol);
  EXPECT_NEAR(last.ranges_m[179], 8.54, kParseTol);
  ExpectPose(*last.laser_pose, 2.289982, -10.869829, 0.207979);
  ExpectPose(*last.robot_pose, 2.074723, -10.915255, 0.207979);
  EXPECT_NEAR(last.stamp_s, 1232663298.321285, 1e-6);
  EXPECT_NEAR(last.logger_stamp_s, 4820.104792, kParseTol);

  // awk: 1748 scans of 181 readings, 5169 of 180 (interleaved start angles).
  int with_181 = 0, with_180 = 0;
  for (const CarmenLaserScan& scan : log.scans) {
    with_181 += scan.ranges_m.size() == 181u;
    with_180 += scan.ranges_m.size() == 180u;
    // Convention check: the laser sits 0.22 m ahead of the base in every
    // line (6-decimal rounding of the log leaves ~1e-6).
    const core::SE2 expected = *scan.robot_pose * core::SE2(0.22, 0.0, 0.0);
    ASSERT_TRUE(scan.laser_pose->IsApprox(expected, 2e-6, 2e-6)) << "line " << scan.line;
  }
  EXPECT_EQ(with_181, 1748);
  EXPECT_EQ(with_180, 5169);
  ExpectScanStampsStrictlyIncrease(log);

  CarmenTrajectoryOptions laser;
  laser.pose_source = CarmenPoseSource::kLaser;
  core::Result<core::Trajectory> odom_traj = CarmenScanTrajectory(log);
  core::Result<core::Trajectory> laser_traj = CarmenScanTrajectory(log, laser);
  ASSERT_TRUE(odom_traj.ok() && laser_traj.ok());
  ASSERT_EQ(odom_traj->size(), 6917u);
  ExpectPose(odom_traj->back().pose, 2.074723, -10.915255, 0.207979);
  ExpectPose(laser_traj->back().pose, 2.289982, -10.869829, 0.207979);
}

}  // namespace
}  // namespace groundline::io
