// io::AttachOdometryPoses: scans that log no pose get the odometry's pose at
// their own stamp (checked against an analytic arc), their laser pose by the
// mounting offset, and what cannot be posed is left out and counted.
#include "groundline/io/carmen_odometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace groundline::io {
namespace {

// A robot on a circle of radius 2 m at 0.5 m/s: T_odom_base(t).
core::SE2 Arc(double t_s) {
  const double yaw = 0.25 * t_s;
  return core::SE2(2.0 * std::sin(yaw), 2.0 * (1.0 - std::cos(yaw)), yaw);
}

std::vector<CarmenOdometry> OdomEvery(double period_s, double from_s, double to_s) {
  std::vector<CarmenOdometry> out;
  const int n = static_cast<int>(std::lround((to_s - from_s) / period_s));
  for (int k = 0; k <= n; ++k) {
    const double t = k == n ? to_s : from_s + k * period_s;
    CarmenOdometry o;
    o.line = static_cast<int64_t>(out.size()) + 1;
    o.stamp_s = t;
    o.pose = Arc(t);
    out.push_back(o);
  }
  return out;
}

CarmenLaserScan RawScan(int64_t line, double stamp_s) {
  CarmenLaserScan s;
  s.line = line;
  s.stamp_s = stamp_s;
  s.message = CarmenLaserMessage::kRawLaser;
  s.ranges_m = {1.0, 2.0};
  return s;
}

TEST(AttachOdometryPoses, InterpolatesBetweenTheOdomReadingsAroundEachScan) {
  const std::vector<CarmenOdometry> odom = OdomEvery(0.05, 0.0, 10.0);  // 20 Hz
  std::vector<CarmenLaserScan> scans;
  for (int i = 0; i < 70; ++i) scans.push_back(RawScan(1000 + i, 0.013 + 0.137 * i));
  std::vector<const CarmenLaserScan*> pointers;
  for (const CarmenLaserScan& s : scans) pointers.push_back(&s);
  CarmenOdometryOptions options;
  options.T_base_laser = core::SE2(0.22, 0.0, 0.0);
  const core::Result<CarmenScansWithOdometry> out = AttachOdometryPoses(pointers, odom, options);
  ASSERT_TRUE(out.ok()) << out.message();
  ASSERT_EQ(out->scans.size(), scans.size());
  EXPECT_EQ(out->attached, 70);
  EXPECT_EQ(out->scans_outside_odometry + out->scans_in_gap + out->odometry_dropped, 0);
  for (const CarmenLaserScan& s : out->scans) {
    ASSERT_TRUE(s.robot_pose && s.laser_pose);
    // Linear interpolation over 2.5 cm of arc: the chord's sagitta, < 0.1 mm.
    EXPECT_TRUE(s.robot_pose->IsApprox(Arc(s.stamp_s), 1e-4, 1e-9)) << "line " << s.line;
    EXPECT_TRUE(s.laser_pose->IsApprox(*s.robot_pose * core::SE2(0.22, 0.0, 0.0), 1e-12, 1e-12));
  }
}

TEST(AttachOdometryPoses, LeavesOutWhatItCannotPoseAndCountsIt) {
  std::vector<CarmenOdometry> odom = OdomEvery(0.1, 1.0, 5.0);
  // A gap of 1 s (3.0 .. 4.0) and one reading written late.
  std::erase_if(odom, [](const CarmenOdometry& o) { return o.stamp_s > 3.05 && o.stamp_s < 3.95; });
  CarmenOdometry late = odom[5];
  late.line = 99;
  odom.insert(odom.begin() + 12, late);
  CarmenLaserScan logged = RawScan(7, 2.0);  // a FLASER line keeps its own pose
  logged.message = CarmenLaserMessage::kFlaser;
  logged.robot_pose = core::SE2(9.0, 9.0, 0.0);
  logged.laser_pose = core::SE2(9.0, 9.0, 0.0);
  const std::vector<CarmenLaserScan> scans = {RawScan(1, 0.5), RawScan(2, 2.05), RawScan(3, 3.5),
                                              logged,          RawScan(4, 5.0),  RawScan(5, 5.2)};
  std::vector<const CarmenLaserScan*> pointers;
  for (const CarmenLaserScan& s : scans) pointers.push_back(&s);
  const core::Result<CarmenScansWithOdometry> out = AttachOdometryPoses(pointers, odom);
  ASSERT_TRUE(out.ok()) << out.message();
  EXPECT_EQ(out->odometry_dropped, 1);
  EXPECT_EQ(out->scans_outside_odometry, 2);  // 0.5 s and 5.2 s
  EXPECT_EQ(out->scans_in_gap, 1);            // 3.5 s
  EXPECT_EQ(out->first_dropped_line, 1);
  EXPECT_EQ(out->attached, 2);  // 2.05 s and 5.0 s (the last reading's own stamp)
  ASSERT_EQ(out->scans.size(), 3u);
  EXPECT_EQ(out->scans[0].line, 2);
  EXPECT_TRUE(out->scans[0].robot_pose->IsApprox(Arc(2.05), 2e-4, 1e-9));  // mid-chord
  EXPECT_EQ(out->scans[1].line, 7);
  EXPECT_TRUE(out->scans[1].robot_pose->IsApprox(core::SE2(9.0, 9.0, 0.0), 0.0, 0.0));
  EXPECT_EQ(out->scans[2].line, 4);
  EXPECT_TRUE(out->scans[2].robot_pose->IsApprox(Arc(5.0), 1e-12, 1e-12));
}

TEST(AttachOdometryPoses, BadInputIsAnErrorThatSaysWhat) {
  std::vector<CarmenOdometry> odom = OdomEvery(0.1, 0.0, 1.0);
  const CarmenLaserScan scan = RawScan(3, 0.5);
  const std::vector<const CarmenLaserScan*> pointers = {&scan};
  CarmenOdometryOptions options;
  options.max_gap_s = 0.0;
  EXPECT_NE(AttachOdometryPoses(pointers, odom, options).message().find("max_gap_s"),
            std::string::npos);
  odom[4].stamp_s = std::nan("");
  EXPECT_NE(AttachOdometryPoses(pointers, odom).message().find("line 5: ODOM"), std::string::npos);
}

TEST(CarmenFrontLaserOffset, ReadsTheParamAndNamesItWhenItIsNotANumber) {
  CarmenLog log;
  EXPECT_FALSE(CarmenFrontLaserOffset(log)->has_value());
  log.params["robot_frontlaser_offset"] = "0.22";
  EXPECT_DOUBLE_EQ(CarmenFrontLaserOffset(log)->value(), 0.22);
  log.params["robot_frontlaser_offset"] = "front";
  const auto bad = CarmenFrontLaserOffset(log);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("robot_frontlaser_offset"), std::string::npos);
}

}  // namespace
}  // namespace groundline::io
