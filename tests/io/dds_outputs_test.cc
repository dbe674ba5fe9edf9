// DdsOutputs and DdsInputs within one process (real DDS, local delivery, no
// network needed): the QoS presets match and refuse as ROS 2's do, a late
// subscriber gets the last pose (transient local), and an initial pose from
// rviz reaches its callback.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>

#include <unistd.h>

#include "dds_test_env.h"
#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_inputs.h"
#include "groundline/io/dds_outputs.h"

namespace groundline::io {
namespace {

class DdsOutputsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::UseLoopbackConfig();
    DdsParticipantOptions options;
    options.domain_id = testing::kInputsDomainId;
    core::Result<DdsParticipant> p = DdsParticipant::Create(options);
    ASSERT_TRUE(p.ok()) << p.message();
    participant_.emplace(std::move(*p));
    prefix_ = "rt/p" + std::to_string(::getpid()) + "/";
  }

  // Takes one sample of T within `timeout` (a guard against a hang, not a measurement).
  template <typename T, typename Fn>
  bool TakeOne(const DdsSubscriber<T>& sub, Fn&& fn) {
    core::Result<DdsWaitSet> ws = DdsWaitSet::Create(*participant_);
    if (!ws.ok() || !ws->Attach(sub.reader()).ok()) return false;
    for (int i = 0; i < 100; ++i) {
      core::Result<bool> ready = ws->Wait(std::chrono::milliseconds(100));
      if (!ready.ok()) return false;
      core::Result<int> n = sub.Take(fn);
      if (n.ok() && *n > 0) return true;
    }
    return false;
  }

  std::optional<DdsParticipant> participant_;
  std::string prefix_;
};

TEST_F(DdsOutputsTest, QosPresetsMatchLikeRos2) {
  auto writer_of = [&](const std::string& topic, QosPreset qos) {
    return DdsPublisher<RosOdometry>::Create(*participant_, prefix_ + topic, qos);
  };
  auto reader_of = [&](const std::string& topic, QosPreset qos) {
    return DdsSubscriber<RosOdometry>::Create(*participant_, prefix_ + topic, qos);
  };
  // Best-effort reader, reliable writer: match.
  auto w1 = writer_of("a", QosPreset::kDefault);
  auto r1 = reader_of("a", QosPreset::kSensorData);
  ASSERT_TRUE(w1.ok() && r1.ok());
  EXPECT_TRUE(WaitForMatches(r1->reader(), false, 1, std::chrono::seconds(10)));
  // Reliable reader, best-effort writer: refused.
  auto w2 = writer_of("b", QosPreset::kSensorData);
  auto r2 = reader_of("b", QosPreset::kDefault);
  ASSERT_TRUE(w2.ok() && r2.ok());
  // A control reader that does match shows the writer has been seen, so a
  // count of 0 on the refusing reader is final.
  auto c2 = reader_of("b", QosPreset::kSensorData);
  ASSERT_TRUE(c2.ok());
  ASSERT_TRUE(WaitForMatches(c2->reader(), false, 1, std::chrono::seconds(10)));
  EXPECT_EQ(*MatchedWriters(r2->reader()), 0u);
  // Transient-local reader, volatile writer: refused.
  auto w3 = writer_of("c", QosPreset::kDefault);
  auto r3 = reader_of("c", QosPreset::kPoseOutput);
  auto c3 = reader_of("c", QosPreset::kDefault);
  ASSERT_TRUE(w3.ok() && r3.ok() && c3.ok());
  ASSERT_TRUE(WaitForMatches(c3->reader(), false, 1, std::chrono::seconds(10)));
  EXPECT_EQ(*MatchedWriters(r3->reader()), 0u);
}

TEST_F(DdsOutputsTest, LateSubscriberGetsTheLastPose) {
  DdsOutputsOptions options;
  options.pose_topic = prefix_ + "groundline/pose";
  options.tf_topic = prefix_ + "tf";
  options.diagnostics_topic = prefix_ + "diagnostics";
  core::Result<DdsOutputs> outputs = DdsOutputs::Create(*participant_, options);
  ASSERT_TRUE(outputs.ok()) << outputs.message();
  core::Matrix3 cov = core::Matrix3::Identity() * 0.01;
  ASSERT_TRUE(outputs->PublishPose(10.0, core::SE2(1.0, 2.0, 0.3), cov).ok());
  ASSERT_TRUE(outputs->PublishPose(10.1, core::SE2(1.5, 2.0, 0.3), cov).ok());

  // Subscribed after both were published; depth 1 keeps the last one.
  auto sub = DdsSubscriber<RosPoseWithCovarianceStamped>::Create(*participant_, options.pose_topic,
                                                                 QosPreset::kPoseOutput);
  ASSERT_TRUE(sub.ok()) << sub.message();
  std::vector<PlanarPoseStamped> got;
  ASSERT_TRUE(TakeOne(*sub, [&](const RosPoseWithCovarianceStamped& m) {
    got.push_back(FromPoseWithCovarianceStamped(m));
  }));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_NEAR(got[0].stamp_s, 10.1, 1e-9);
  EXPECT_EQ(got[0].frame_id, "map");
  EXPECT_TRUE(got[0].T_frame_base.IsApprox(core::SE2(1.5, 2.0, 0.3), 1e-12, 1e-12));
  EXPECT_TRUE(got[0].covariance.isApprox(cov, 1e-12));

  auto tf = DdsSubscriber<RosTfMessage>::Create(*participant_, options.tf_topic, QosPreset::kTf);
  ASSERT_TRUE(tf.ok());
  ASSERT_TRUE(outputs->PublishMapToOdom(10.1, core::SE2(0.1, -0.2, 0.05)).ok());
  std::string parent, child;
  ASSERT_TRUE(TakeOne(*tf, [&](const RosTfMessage& m) {
    ASSERT_EQ(m.transforms._length, 1u);
    parent = m.transforms._buffer[0].header.frame_id;
    child = m.transforms._buffer[0].child_frame_id;
  }));
  EXPECT_EQ(parent, "map");
  EXPECT_EQ(child, "odom");
}

TEST_F(DdsOutputsTest, InitialPoseReachesItsCallbackAndWrongFrameIsDropped) {
  std::vector<PlanarPoseStamped> poses;
  DdsInputCallbacks cb;
  cb.on_initial_pose = [&](const PlanarPoseStamped& p) { poses.push_back(p); };
  DdsInputsOptions options;
  options.odometry_topic = options.joint_state_topic = options.scan_topic = options.image_topic =
      "";
  options.initial_pose_topic = prefix_ + "initialpose";
  core::Result<DdsInputs> inputs = DdsInputs::Create(*participant_, options, cb);
  ASSERT_TRUE(inputs.ok()) << inputs.message();
  auto rviz = DdsPublisher<RosPoseWithCovarianceStamped>::Create(
      *participant_, options.initial_pose_topic, QosPreset::kDefault);
  ASSERT_TRUE(rviz.ok());
  PlanarPoseStamped wrong;
  wrong.stamp_s = 1.0;
  wrong.frame_id = "odom";
  PlanarPoseStamped right;
  right.stamp_s = 2.0;
  right.frame_id = "map";
  right.T_frame_base = core::SE2(4.0, 5.0, -1.0);
  // Commands, not a stream: one stamped earlier, and two unset stamps
  // (`ros2 topic pub` twice), are each taken.
  PlanarPoseStamped earlier = right;
  earlier.stamp_s = 1.5;
  PlanarPoseStamped unset = right;
  unset.stamp_s = 0.0;
  ASSERT_TRUE(rviz->Write(ToPoseWithCovarianceStamped(wrong).msg()).ok());
  ASSERT_TRUE(rviz->Write(ToPoseWithCovarianceStamped(right).msg()).ok());
  ASSERT_TRUE(rviz->Write(ToPoseWithCovarianceStamped(earlier).msg()).ok());
  ASSERT_TRUE(rviz->Write(ToPoseWithCovarianceStamped(unset).msg()).ok());
  ASSERT_TRUE(rviz->Write(ToPoseWithCovarianceStamped(unset).msg()).ok());
  for (int i = 0; i < 100 && inputs->counters(DdsInput::kInitialPose).received < 5; ++i) {
    ASSERT_TRUE(inputs->Poll(std::chrono::milliseconds(100)).ok());
  }
  ASSERT_EQ(poses.size(), 4u);
  EXPECT_TRUE(poses[0].T_frame_base.IsApprox(right.T_frame_base, 1e-12, 1e-12));
  EXPECT_DOUBLE_EQ(poses[1].stamp_s, 1.5);
  EXPECT_DOUBLE_EQ(poses[3].stamp_s, 0.0);
  const DdsInputCounters& c = inputs->counters(DdsInput::kInitialPose);
  EXPECT_EQ(c.dropped, 1u);
  EXPECT_NE(c.last_drop_reason.find("'header.frame_id': expected 'map', got 'odom'"),
            std::string::npos)
      << c.last_drop_reason;
}

TEST_F(DdsOutputsTest, OnePollDeliversSensorDataInStampOrder) {
  std::vector<std::string> order;
  DdsInputCallbacks cb;
  cb.on_odometry = [&](const PlanarOdometry& o) {
    order.push_back("odom@" + std::to_string(o.stamp_s));
  };
  cb.on_scan = [&](const core::LaserScan& s) {
    order.push_back("scan@" + std::to_string(s.stamp_s));
  };
  DdsInputsOptions options;
  options.odometry_topic = prefix_ + "odom";
  options.scan_topic = prefix_ + "scan";
  options.joint_state_topic = options.image_topic = options.initial_pose_topic = "";
  options.stamp_reference = StampReference::kNone;
  options.sensor_qos = QosPreset::kLossless;
  core::Result<DdsInputs> inputs = DdsInputs::Create(*participant_, options, cb);
  ASSERT_TRUE(inputs.ok()) << inputs.message();
  auto odom = DdsPublisher<RosOdometry>::Create(*participant_, options.odometry_topic,
                                                QosPreset::kLossless);
  auto scan =
      DdsPublisher<RosLaserScan>::Create(*participant_, options.scan_topic, QosPreset::kLossless);
  ASSERT_TRUE(odom.ok() && scan.ok());
  core::LaserScan s;
  s.angle_increment_rad = 0.1;
  s.range_min_m = 0.1;
  s.range_max_m = 10.0;
  s.ranges_m = {1.0, 2.0};
  // Scans written first, odometry second; stamps interleave.
  for (double t : {2.0, 4.0}) {
    s.stamp_s = t;
    ASSERT_TRUE(scan->Write(ToLaserScan(s, "laser").msg()).ok());
  }
  for (double t : {1.0, 3.0, 5.0}) {
    PlanarOdometry o;
    o.stamp_s = t;
    ASSERT_TRUE(odom->Write(ToOdometry(o).msg()).ok());
  }
  // Local delivery is synchronous for these keep-all readers: one Poll sees all five.
  core::Result<int> n = inputs->Poll(std::chrono::milliseconds(1000));
  ASSERT_TRUE(n.ok()) << n.message();
  ASSERT_EQ(*n, 5);
  const std::vector<std::string> want = {"odom@1.000000", "scan@2.000000", "odom@3.000000",
                                         "scan@4.000000", "odom@5.000000"};
  EXPECT_EQ(order, want);
}

TEST_F(DdsOutputsTest, OlderMessagesAreDroppedUntilARunOfThemRevealsAClockStep) {
  std::vector<double> stamps;
  DdsInputCallbacks cb;
  cb.on_odometry = [&](const PlanarOdometry& o) { stamps.push_back(o.stamp_s); };
  DdsInputsOptions options;
  options.odometry_topic = prefix_ + "odom_order";
  options.joint_state_topic = options.scan_topic = options.image_topic =
      options.initial_pose_topic = "";
  options.stamp_reference = StampReference::kNone;
  options.sensor_qos = QosPreset::kLossless;
  options.clock_step_messages = 4;
  core::Result<DdsInputs> inputs = DdsInputs::Create(*participant_, options, cb);
  ASSERT_TRUE(inputs.ok()) << inputs.message();
  auto odom = DdsPublisher<RosOdometry>::Create(*participant_, options.odometry_topic,
                                                QosPreset::kLossless);
  ASSERT_TRUE(odom.ok());
  // 3.0 arrives after 4.0 (a reordering transport: an absolute pose older
  // than the newest adds nothing), 4.0 twice; then the sender's clock steps
  // back by 100 s and the drive goes on.
  for (double t : {1.0, 2.0, 4.0, 3.0, 4.0, 5.0, -95.0, -94.0, -93.0, -92.0, -91.0, -90.0}) {
    PlanarOdometry o;
    o.stamp_s = t;
    ASSERT_TRUE(odom->Write(ToOdometry(o).msg()).ok());
    ASSERT_TRUE(inputs->Poll(std::chrono::milliseconds(1000)).ok());
  }
  const DdsInputCounters& c = inputs->counters(DdsInput::kOdometry);
  EXPECT_EQ(c.received, 12u);
  EXPECT_EQ(c.clock_steps, 1u);
  EXPECT_EQ(c.dropped, 5u);  // 3.0, the second 4.0, and -95 .. -93 before the step is clear
  EXPECT_EQ(stamps, (std::vector<double>{1.0, 2.0, 4.0, 5.0, -92.0, -91.0, -90.0}));
}

TEST(DdsOptionsTest, ValidateNamesTheProblem) {
  DdsInputsOptions in;
  EXPECT_TRUE(in.Validate().ok());
  in.scan_topic = "/scan";  // a ROS name, not a DDS topic name
  EXPECT_NE(in.Validate().message().find("'/scan' must start with 'rt/'"), std::string::npos);
  in = {};
  in.right_wheel_joint = in.left_wheel_joint;
  EXPECT_FALSE(in.Validate().ok());
  DdsOutputsOptions out;
  out.map_frame.clear();
  EXPECT_FALSE(out.Validate().ok());
  DdsParticipantOptions p;
  p.domain_id = 300;
  EXPECT_NE(p.Validate().message().find("domain_id"), std::string::npos);
}

}  // namespace
}  // namespace groundline::io
