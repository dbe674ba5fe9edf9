// Conversions between groundline types and ROS 2 messages, and the checks
// that reject bad incoming messages with a message naming type and field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <opencv2/core.hpp>

#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_validate.h"

namespace groundline::io {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

core::LaserScan MakeScan() {
  core::LaserScan s;
  s.stamp_s = 100.25;
  s.angle_min_rad = -1.0;
  s.angle_increment_rad = 0.01;
  s.range_min_m = 0.05;
  s.range_max_m = 30.0;
  for (int i = 0; i < 201; ++i) s.ranges_m.push_back(i % 7 == 0 ? 0.0 : 1.0 + 0.01 * i);
  return s;
}

void ExpectErrorMentions(const core::Status& s, const std::string& a, const std::string& b) {
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find(a), std::string::npos) << s.message();
  EXPECT_NE(s.message().find(b), std::string::npos) << s.message();
}

TEST(DdsConvertTest, RosTimeRoundsToNanosecondsAndCarries) {
  RosTime t = ToRosTime(12.5);
  EXPECT_EQ(t.sec, 12);
  EXPECT_EQ(t.nanosec, 500000000u);
  t = ToRosTime(1.9999999999);  // rounds up to the next second
  EXPECT_EQ(t.sec, 2);
  EXPECT_EQ(t.nanosec, 0u);
  t = ToRosTime(-0.25);
  EXPECT_EQ(t.sec, -1);
  EXPECT_EQ(t.nanosec, 750000000u);
  EXPECT_NEAR(FromRosTime(ToRosTime(1700000000.123456789)), 1700000000.123456789, 1e-6);
}

TEST(DdsConvertTest, PoseCovarianceGoesToRowsXYRotZInParentFrame) {
  PlanarPoseStamped p;
  p.frame_id = "map";
  p.T_frame_base = core::SE2(1.0, 2.0, M_PI / 2);
  // Tangent space: 0.04 m^2 along the robot's x, 0.01 across, yaw 0.0025.
  p.covariance = core::Vector3(0.04, 0.01, 0.0025).asDiagonal();
  p.covariance(0, 2) = p.covariance(2, 0) = 0.001;
  const DdsSample<RosPoseWithCovarianceStamped> m = ToPoseWithCovarianceStamped(p);
  const double* c = m.msg().pose.covariance;
  // Facing +y: the robot's x variance is the map's y variance.
  EXPECT_NEAR(c[0 * 6 + 0], 0.01, 1e-12);
  EXPECT_NEAR(c[1 * 6 + 1], 0.04, 1e-12);
  EXPECT_NEAR(c[5 * 6 + 5], 0.0025, 1e-12);
  EXPECT_NEAR(c[1 * 6 + 5], 0.001, 1e-12);
  EXPECT_NEAR(c[5 * 6 + 1], 0.001, 1e-12);
  EXPECT_NEAR(c[0 * 6 + 5], 0.0, 1e-12);
  EXPECT_EQ(c[2 * 6 + 2], kUnobservedVariance);
  EXPECT_EQ(c[3 * 6 + 3], kUnobservedVariance);
  EXPECT_EQ(c[4 * 6 + 4], kUnobservedVariance);
  const PlanarPoseStamped back = FromPoseWithCovarianceStamped(m.msg());
  EXPECT_TRUE(back.T_frame_base.IsApprox(p.T_frame_base, 1e-12, 1e-12));
  EXPECT_TRUE(back.covariance.isApprox(p.covariance, 1e-12));
  EXPECT_EQ(back.frame_id, "map");
}

TEST(DdsConvertTest, YawSurvivesTheQuaternionNearPi) {
  for (double yaw : {0.0, 1e-9, 3.14159, -3.14159, M_PI, -2.0}) {
    PlanarOdometry o;
    o.T_odom_base = core::SE2(0.0, 0.0, yaw);
    const PlanarOdometry back = FromOdometry(ToOdometry(o).msg());
    EXPECT_TRUE(back.T_odom_base.IsApprox(o.T_odom_base, 1e-12, 1e-12)) << yaw;
  }
}

TEST(DdsConvertTest, LaserScanRoundTripKeepsNoReturnsAndCount) {
  const core::LaserScan scan = MakeScan();
  const DdsSample<RosLaserScan> m = ToLaserScan(scan, "laser");
  EXPECT_TRUE(ValidateLaserScan(m.msg(), {}).ok());
  EXPECT_TRUE(std::isinf(m.msg().ranges._buffer[0]));
  const core::LaserScan back = FromLaserScan(m.msg());
  ASSERT_EQ(back.ranges_m.size(), scan.ranges_m.size());
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    EXPECT_NEAR(back.ranges_m[i], scan.ranges_m[i], 1e-6) << i;
  }
  EXPECT_NEAR(back.BeamAngle_rad(200), scan.BeamAngle_rad(200), 1e-6);
}

TEST(DdsConvertTest, ImageRoundTripAndWrongEncoding) {
  cv::Mat grey(4, 5, CV_8UC1);
  for (int i = 0; i < 20; ++i) grey.data[i] = static_cast<std::uint8_t>(i * 11);
  DdsSample<RosImage> m = ToMono8Image(grey, 1.0, "cam");
  core::Result<cv::Mat> back = FromMono8Image(m.msg());
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(cv::countNonZero(*back != grey), 0);
  dds_free(m.msg().encoding);
  m.msg().encoding = DdsStringDup("rgb8");
  ExpectErrorMentions(ValidateImage(m.msg(), {}), "sensor_msgs/Image", "'encoding'");
  EXPECT_FALSE(FromMono8Image(m.msg()).ok());
}

TEST(DdsValidateTest, LaserScanWithWrongRangeCountIsRejected) {
  DdsSample<RosLaserScan> m = ToLaserScan(MakeScan(), "laser");
  m.msg().ranges._length -= 1;  // 200 values for 201 beams
  ExpectErrorMentions(ValidateLaserScan(m.msg(), {}), "sensor_msgs/LaserScan", "'ranges'");
  m.msg().ranges._length += 1;
  m.msg().angle_max += m.msg().angle_increment;  // off by one beam the other way
  ExpectErrorMentions(ValidateLaserScan(m.msg(), {}), "sensor_msgs/LaserScan", "'ranges'");
}

TEST(DdsValidateTest, NaNFieldsAreRejected) {
  DdsSample<RosLaserScan> scan = ToLaserScan(MakeScan(), "laser");
  scan.msg().angle_increment = std::numeric_limits<float>::quiet_NaN();
  ExpectErrorMentions(ValidateLaserScan(scan.msg(), {}), "sensor_msgs/LaserScan",
                      "'angle_increment'");

  PlanarOdometry o;
  DdsSample<RosOdometry> odom = ToOdometry(o);
  EXPECT_TRUE(ValidateOdometry(odom.msg(), {}).ok());
  odom.msg().pose.pose.position.y = kNaN;
  ExpectErrorMentions(ValidateOdometry(odom.msg(), {}), "nav_msgs/Odometry",
                      "'pose.pose.position.y'");
  odom = ToOdometry(o);
  odom.msg().twist.covariance[7] = kNaN;
  ExpectErrorMentions(ValidateOdometry(odom.msg(), {}), "nav_msgs/Odometry",
                      "'twist.covariance[7]'");

  PlanarPoseStamped p;
  DdsSample<RosPoseWithCovarianceStamped> pose = ToPoseWithCovarianceStamped(p);
  pose.msg().pose.pose.orientation.w = 0.5;  // not a unit quaternion
  ExpectErrorMentions(ValidatePoseWithCovarianceStamped(pose.msg(), {}),
                      "geometry_msgs/PoseWithCovarianceStamped", "'pose.pose.orientation'");

  WheelJointState js;
  js.names = {"l", "r"};
  js.position_rad = {0.0, kNaN};
  ExpectErrorMentions(ValidateJointState(ToJointState(js).msg(), {}, {"l", "r"}),
                      "sensor_msgs/JointState", "'position[1] (r)'");
}

TEST(DdsValidateTest, WrongFrameIdIsRejected) {
  DdsCheck check;
  check.frame_id = "laser";
  EXPECT_TRUE(ValidateLaserScan(ToLaserScan(MakeScan(), "laser").msg(), check).ok());
  ExpectErrorMentions(ValidateLaserScan(ToLaserScan(MakeScan(), "base_scan").msg(), check),
                      "'header.frame_id'", "expected 'laser', got 'base_scan'");
  PlanarOdometry o;
  o.base_frame = "base_footprint";
  ExpectErrorMentions(ValidateOdometry(ToOdometry(o).msg(), {}, "base_link"), "nav_msgs/Odometry",
                      "'child_frame_id'");
}

TEST(DdsValidateTest, StampsOutsideTheWindowAreRejected) {
  const DdsSample<RosLaserScan> m = ToLaserScan(MakeScan(), "laser");  // stamp 100.25
  DdsCheck check;
  check.window.max_stamp_age_s = 1.0;
  check.window.max_stamp_lead_s = 0.2;
  check.reference_s = 101.0;  // 0.75 s old: fine
  EXPECT_TRUE(ValidateLaserScan(m.msg(), check).ok());
  check.reference_s = 101.5;  // 1.25 s old
  ExpectErrorMentions(ValidateLaserScan(m.msg(), check), "sensor_msgs/LaserScan", "'header.stamp'");
  check.reference_s = 100.0;  // 0.25 s in the future
  ExpectErrorMentions(ValidateLaserScan(m.msg(), check), "sensor_msgs/LaserScan", "'header.stamp'");
  check.reference_s = 100.1;  // 0.15 s ahead: within the lead
  EXPECT_TRUE(ValidateLaserScan(m.msg(), check).ok());
}

TEST(DdsValidateTest, JointStateMissingOrDuplicatedWheel) {
  WheelJointState js;
  js.names = {"left_wheel_joint", "caster"};
  js.position_rad = {1.0, 2.0};
  ExpectErrorMentions(
      ValidateJointState(ToJointState(js).msg(), {}, {"left_wheel_joint", "right_wheel_joint"}),
      "sensor_msgs/JointState", "'right_wheel_joint' missing");
  js.names = {"left_wheel_joint", "left_wheel_joint"};
  ExpectErrorMentions(ValidateJointState(ToJointState(js).msg(), {}, {"left_wheel_joint"}),
                      "sensor_msgs/JointState", "listed twice");
}

TEST(DdsValidateTest, OptionsValidate) {
  DdsStampWindow w;
  EXPECT_TRUE(w.Validate().ok());
  w.max_stamp_age_s = -1.0;
  EXPECT_FALSE(w.Validate().ok());
}

}  // namespace
}  // namespace groundline::io
