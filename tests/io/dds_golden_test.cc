// Golden vectors: the bytes CycloneDDS serializes for each ROS 2 message type
// equal the plain-CDR layout of ROS 2 Humble derived by hand (dds_cdr_builder.h).
// The bytes are those a writer hands to the transport: a sample written by a
// writer and taken as serialized data (dds_takecdr) by a reader of the same
// participant, so no network is involved.
#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include <unistd.h>

#include "dds_cdr_builder.h"
#include "dds_test_env.h"
#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_pubsub.h"

namespace groundline::io {
namespace {

using testing::CdrBuilder;

class DdsGoldenTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    testing::UseLoopbackConfig();
    DdsParticipantOptions options;
    options.domain_id = testing::kGoldenDomainId;
    core::Result<DdsParticipant> p = DdsParticipant::Create(options);
    ASSERT_TRUE(p.ok()) << p.message();
    participant_ = new DdsParticipant(std::move(*p));
  }
  static void TearDownTestSuite() {
    delete participant_;
    participant_ = nullptr;
  }

  // The serialized sample, encapsulation header included.
  template <typename T>
  std::vector<std::uint8_t> WireBytes(const T& msg) {
    // The pid keeps topics of golden tests run in parallel (same domain) apart.
    const std::string topic =
        "rt/golden/p" + std::to_string(::getpid()) + "/t" + std::to_string(next_topic_++);
    core::Result<DdsPublisher<T>> pub =
        DdsPublisher<T>::Create(*participant_, topic, QosPreset::kDefault);
    core::Result<DdsSubscriber<T>> sub =
        DdsSubscriber<T>::Create(*participant_, topic, QosPreset::kDefault);
    EXPECT_TRUE(pub.ok() && sub.ok());
    if (!pub.ok() || !sub.ok()) return {};
    EXPECT_TRUE(WaitForMatches(pub->writer(), true, 1, std::chrono::seconds(10)));
    const core::Status written = pub->Write(msg);
    EXPECT_TRUE(written.ok()) << written.message();
    ddsi_serdata* sd = nullptr;
    dds_sample_info_t info;
    dds_return_t n = 0;
    for (int i = 0; i < 1000 && n == 0; ++i) {
      n = dds_takecdr(sub->reader().get(), &sd, 1, &info, DDS_ANY_STATE);
      if (n == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_EQ(n, 1);
    if (n != 1) return {};
    std::vector<std::uint8_t> bytes(ddsi_serdata_size(sd));
    ddsi_serdata_to_ser(sd, 0, bytes.size(), bytes.data());
    ddsi_serdata_unref(sd);
    return bytes;
  }

  static DdsParticipant* participant_;
  int next_topic_ = 0;
};
DdsParticipant* DdsGoldenTest::participant_ = nullptr;

std::string Hex(const std::vector<std::uint8_t>& b, std::size_t from, std::size_t to) {
  std::string s;
  char buf[4];
  for (std::size_t i = from; i < to && i < b.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%02x ", b[i]);
    s += buf;
  }
  return s;
}

// Header and payload equal; a tail of padding (0-3 zero bytes, its length in
// the options' low bits) is allowed.
void ExpectWire(const std::vector<std::uint8_t>& actual,
                const std::vector<std::uint8_t>& expected) {
  ASSERT_GE(actual.size(), expected.size()) << "actual: " << Hex(actual, 0, actual.size());
  const std::size_t pad = actual.size() - expected.size();
  ASSERT_LT(pad, 4u) << "actual: " << Hex(actual, 0, actual.size());
  EXPECT_EQ(actual[0], 0x00);
  EXPECT_EQ(actual[1], 0x01) << "expected CDR_LE (plain XCDR1), got encapsulation "
                             << Hex(actual, 0, 2);
  EXPECT_EQ(actual[2], 0x00);
  EXPECT_EQ(actual[3] & 0x03u, pad);
  for (std::size_t i = 4; i < expected.size(); ++i) {
    ASSERT_EQ(actual[i], expected[i]) << "first difference at payload offset " << i - 4
                                      << "\nactual:   " << Hex(actual, 4, actual.size())
                                      << "\nexpected: " << Hex(expected, 4, expected.size());
  }
  for (std::size_t i = expected.size(); i < actual.size(); ++i) EXPECT_EQ(actual[i], 0);
}

TEST_F(DdsGoldenTest, TypeNamesAreThoseOfRos2) {
  EXPECT_STREQ(DdsTraits<RosPoseWithCovarianceStamped>::descriptor().m_typename,
               "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_");
  EXPECT_STREQ(DdsTraits<RosTfMessage>::descriptor().m_typename, "tf2_msgs::msg::dds_::TFMessage_");
  EXPECT_STREQ(DdsTraits<RosOdometry>::descriptor().m_typename, "nav_msgs::msg::dds_::Odometry_");
  EXPECT_STREQ(DdsTraits<RosLaserScan>::descriptor().m_typename,
               "sensor_msgs::msg::dds_::LaserScan_");
  EXPECT_STREQ(DdsTraits<RosImage>::descriptor().m_typename, "sensor_msgs::msg::dds_::Image_");
  EXPECT_STREQ(DdsTraits<RosJointState>::descriptor().m_typename,
               "sensor_msgs::msg::dds_::JointState_");
  EXPECT_STREQ(DdsTraits<RosDiagnosticArray>::descriptor().m_typename,
               "diagnostic_msgs::msg::dds_::DiagnosticArray_");
  // No keys: ROS 2 topics are keyless.
  EXPECT_EQ(DdsTraits<RosOdometry>::descriptor().m_nkeys, 0u);
}

// One vector written out byte by byte, so the builder's rules are pinned too.
TEST_F(DdsGoldenTest, JointStateLiteralBytes) {
  WheelJointState js;
  js.stamp_s = 1.000000002;
  js.names = {"left"};
  js.position_rad = {1.5};
  const std::vector<std::uint8_t> expected = {
      0x00, 0x01, 0x00, 0x00,                          // CDR_LE
      0x01, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00,  // stamp 1 s 2 ns
      0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // frame_id "" + 3 pad
      0x01, 0x00, 0x00, 0x00,                          // name: 1 string
      0x05, 0x00, 0x00, 0x00, 'l',  'e',  'f',  't',  0x00, 0x00, 0x00, 0x00,  // "left" + 3 pad
      0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // position: 1 double, pad to 8
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf8, 0x3f,  // 1.5
      0x00, 0x00, 0x00, 0x00,                          // velocity: 0
      0x00, 0x00, 0x00, 0x00};                         // effort: 0
  ExpectWire(WireBytes(ToJointState(js).msg()), expected);
  CdrBuilder b;
  b.Header(1, 2, "").Count(1).Str("left").Count(1).F64(1.5).Count(0).Count(0);
  EXPECT_EQ(b.bytes(), expected);
}

TEST_F(DdsGoldenTest, PoseWithCovarianceStamped) {
  PlanarPoseStamped p;
  p.stamp_s = 1700000000.25;
  p.frame_id = "map";
  p.T_frame_base = core::SE2(1.5, -2.0, 0.5);
  p.covariance << 0.04, 0.01, 0.002, 0.01, 0.09, 0.003, 0.002, 0.003, 0.0025;
  const DdsSample<RosPoseWithCovarianceStamped> msg = ToPoseWithCovarianceStamped(p);
  CdrBuilder b;
  b.Header(1700000000, 250000000, "map");
  b.F64(1.5).F64(-2.0).F64(0.0);                                // position
  b.F64(0.0).F64(0.0).F64(std::sin(0.25)).F64(std::cos(0.25));  // orientation
  for (double c : msg.msg().pose.covariance) b.F64(c);          // double[36], no count
  ExpectWire(WireBytes(msg.msg()), b.bytes());
}

TEST_F(DdsGoldenTest, Odometry) {
  PlanarOdometry o;
  o.stamp_s = 12.5;
  o.T_odom_base = core::SE2(3.0, 4.0, -1.0);
  o.covariance = core::Matrix3::Identity() * 0.01;
  o.forward_velocity_mps = 0.8;
  o.yaw_rate_radps = -0.1;
  o.twist_covariance = core::Matrix3::Identity() * 0.001;
  const DdsSample<RosOdometry> msg = ToOdometry(o);
  CdrBuilder b;
  b.Header(12, 500000000, "odom").Str("base_link");
  b.F64(3.0).F64(4.0).F64(0.0).F64(0.0).F64(0.0).F64(std::sin(-0.5)).F64(std::cos(-0.5));
  for (double c : msg.msg().pose.covariance) b.F64(c);
  b.F64(0.8).F64(0.0).F64(0.0).F64(0.0).F64(0.0).F64(-0.1);  // twist linear, angular
  for (double c : msg.msg().twist.covariance) b.F64(c);
  ExpectWire(WireBytes(msg.msg()), b.bytes());
}

TEST_F(DdsGoldenTest, TfMessageMapToOdom) {
  const DdsSample<RosTfMessage> msg =
      ToTfMessage({{7.0, "map", "odom", core::SE2(0.5, 0.25, 0.1)},
                   {7.0, "odom", "base_link", core::SE2(1.0, 0.0, 0.0)}});
  CdrBuilder b;
  b.Count(2);
  b.Header(7, 0, "map").Str("odom");
  b.F64(0.5).F64(0.25).F64(0.0).F64(0.0).F64(0.0).F64(std::sin(0.05)).F64(std::cos(0.05));
  b.Header(7, 0, "odom").Str("base_link");
  b.F64(1.0).F64(0.0).F64(0.0).F64(0.0).F64(0.0).F64(0.0).F64(1.0);
  ExpectWire(WireBytes(msg.msg()), b.bytes());
}

TEST_F(DdsGoldenTest, LaserScan) {
  core::LaserScan scan;
  scan.stamp_s = 3.5;
  scan.angle_min_rad = -0.5;
  scan.angle_increment_rad = 0.25;
  scan.range_min_m = 0.05;
  scan.range_max_m = 20.0;
  scan.ranges_m = {1.0, core::kNoReturnRange_m, 2.5, 3.0, 19.5};
  scan.intensities = {10, 0, 20, 30, 5};
  const DdsSample<RosLaserScan> msg = ToLaserScan(scan, "laser", 0.1);
  CdrBuilder b;
  b.Header(3, 500000000, "laser");
  b.F32(-0.5f).F32(0.5f).F32(0.25f).F32(0.0f).F32(0.1f).F32(0.05f).F32(20.0f);
  b.Count(5).F32(1.0f).F32(std::numeric_limits<float>::infinity()).F32(2.5f).F32(3.0f).F32(19.5f);
  b.Count(5).F32(10).F32(0).F32(20).F32(30).F32(5);
  ExpectWire(WireBytes(msg.msg()), b.bytes());
}

TEST_F(DdsGoldenTest, Mono8Image) {
  cv::Mat grey(2, 3, CV_8UC1);
  for (int i = 0; i < 6; ++i) grey.data[i] = static_cast<std::uint8_t>(10 * i + 1);
  const DdsSample<RosImage> msg = ToMono8Image(grey, 0.5, "camera_optical");
  CdrBuilder b;
  b.Header(0, 500000000, "camera_optical");
  b.U32(2).U32(3).Str("mono8").U8(0).U32(3);  // height, width, encoding, is_bigendian, step
  b.Count(6);
  for (int i = 0; i < 6; ++i) b.U8(static_cast<std::uint8_t>(10 * i + 1));
  ExpectWire(WireBytes(msg.msg()), b.bytes());
}

TEST_F(DdsGoldenTest, JointStateTwoWheelsWithVelocity) {
  WheelJointState js;
  js.stamp_s = 2.0;
  js.frame_id = "base_link";
  js.names = {"left_wheel_joint", "right_wheel_joint"};
  js.position_rad = {0.125, -3.5};
  js.velocity_radps = {1.0, 2.0};
  CdrBuilder b;
  b.Header(2, 0, "base_link");
  b.Count(2).Str("left_wheel_joint").Str("right_wheel_joint");
  b.Count(2).F64(0.125).F64(-3.5);
  b.Count(2).F64(1.0).F64(2.0);
  b.Count(0);
  ExpectWire(WireBytes(ToJointState(js).msg()), b.bytes());
}

TEST_F(DdsGoldenTest, DiagnosticArray) {
  DiagnosticEntry e;
  e.level = DiagnosticLevel::kWarn;
  e.name = "groundline: localizer";
  e.message = "degenerate";
  e.hardware_id = "agv7";
  e.values = {{"line_rate_hz", "2.5"}, {"slip", "x"}};
  DiagnosticEntry ok;
  ok.name = "groundline: dds";
  const DdsSample<RosDiagnosticArray> msg = ToDiagnosticArray(9.75, {e, ok});
  CdrBuilder b;
  b.Header(9, 750000000, "");
  b.Count(2);
  b.U8(1).Str("groundline: localizer").Str("degenerate").Str("agv7");
  b.Count(2).Str("line_rate_hz").Str("2.5").Str("slip").Str("x");
  b.U8(0).Str("groundline: dds").Str("").Str("").Count(0);
  ExpectWire(WireBytes(msg.msg()), b.bytes());
}

}  // namespace
}  // namespace groundline::io
