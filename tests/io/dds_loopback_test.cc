// End to end over real CycloneDDS participants in two processes on the
// loopback configuration: io_dds_test_publisher (forked and exec'd) sends
// odometry, joint states, scans and images plus three bad messages; this
// process receives them through DdsInputs and checks every message arrived,
// in order, with its contents, and that the bad ones were dropped and
// counted. Nothing timing-related is measured; the deadlines only keep a
// broken setup from hanging the test.
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "dds_loopback_messages.h"
#include "dds_test_env.h"
#include "groundline/io/dds_inputs.h"

extern char** environ;

namespace groundline::io {
namespace {

struct Received {
  std::vector<PlanarOdometry> odometry;
  std::vector<core::WheelEncoderReading> wheels;
  std::vector<core::LaserScan> scans;
  std::vector<std::pair<double, cv::Mat>> images;
};

pid_t SpawnPublisher(unsigned domain_id, const std::string& prefix) {
  const std::string path = GROUNDLINE_DDS_TEST_PUBLISHER;
  const std::string domain = std::to_string(domain_id);
  char* argv[] = {const_cast<char*>(path.c_str()), const_cast<char*>(domain.c_str()),
                  const_cast<char*>(prefix.c_str()), nullptr};
  pid_t pid = -1;
  if (posix_spawn(&pid, path.c_str(), nullptr, nullptr, argv, environ) != 0) return -1;
  return pid;
}

TEST(DdsLoopbackTest, EveryMessageFromAnotherProcessArrivesIntact) {
  testing::UseLoopbackConfig();
  DdsParticipantOptions participant_options;
  participant_options.domain_id = testing::kLoopbackDomainId;
  core::Result<DdsParticipant> participant = DdsParticipant::Create(participant_options);
  ASSERT_TRUE(participant.ok()) << participant.message();
  EXPECT_EQ(participant->config_source(), "CYCLONEDDS_URI");

  Received got;
  DdsInputCallbacks callbacks;
  callbacks.on_odometry = [&](const PlanarOdometry& o) { got.odometry.push_back(o); };
  callbacks.on_wheels = [&](const core::WheelEncoderReading& w) { got.wheels.push_back(w); };
  callbacks.on_scan = [&](const core::LaserScan& s) { got.scans.push_back(s); };
  callbacks.on_image = [&](double t, const cv::Mat& m) { got.images.emplace_back(t, m.clone()); };
  // Topics under a prefix of this process: another run of this test at the
  // same time (a second build tree) shares the domain but not the topics.
  const std::string prefix = "rt/t" + std::to_string(::getpid()) + "/";
  DdsInputsOptions options;
  options.odometry_topic = prefix + "odom";
  options.joint_state_topic = prefix + "joint_states";
  options.scan_topic = prefix + "scan";
  options.image_topic = prefix + "camera/image_raw";
  options.initial_pose_topic.clear();
  options.sensor_qos = QosPreset::kLossless;
  options.stamp_reference = StampReference::kNewest;
  options.stamp_window.max_stamp_age_s = 10.0;
  options.camera_frame = "camera_optical";
  core::Result<DdsInputs> inputs = DdsInputs::Create(*participant, options, callbacks);
  ASSERT_TRUE(inputs.ok()) << inputs.message();

  const pid_t pid = SpawnPublisher(testing::kLoopbackDomainId, prefix);
  ASSERT_GT(pid, 0) << "cannot start " << GROUNDLINE_DDS_TEST_PUBLISHER;
  const int n = testing::kLoopbackMessages;
  auto complete = [&] {
    return static_cast<int>(got.odometry.size()) == n && static_cast<int>(got.wheels.size()) == n &&
           static_cast<int>(got.scans.size()) == n && static_cast<int>(got.images.size()) == n &&
           inputs->counters(DdsInput::kScan).dropped == 2 &&
           inputs->counters(DdsInput::kOdometry).dropped == 1;
  };
  int status = 0;
  bool exited = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    core::Result<int> polled = inputs->Poll(std::chrono::milliseconds(100));
    ASSERT_TRUE(polled.ok()) << polled.message();
    if (!exited && waitpid(pid, &status, WNOHANG) == pid) exited = true;
    // The publisher exits once everything is acknowledged, i.e. in our history.
    if (exited && complete()) break;
  }
  if (!exited) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    FAIL() << "the publisher did not finish";
  }
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0) << "see the publisher's stderr";
  inputs->Poll(std::chrono::milliseconds(0)).ok();

  ASSERT_EQ(static_cast<int>(got.odometry.size()), n);
  ASSERT_EQ(static_cast<int>(got.wheels.size()), n);
  ASSERT_EQ(static_cast<int>(got.scans.size()), n);
  ASSERT_EQ(static_cast<int>(got.images.size()), n);
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE("message " + std::to_string(i));
    const PlanarOdometry want = testing::LoopbackOdometry(i);
    const PlanarOdometry& o = got.odometry[i];
    EXPECT_NEAR(o.stamp_s, want.stamp_s, 1e-9);
    EXPECT_EQ(o.odom_frame, "odom");
    EXPECT_EQ(o.base_frame, "base_link");
    EXPECT_TRUE(o.T_odom_base.IsApprox(want.T_odom_base, 1e-12, 1e-12));
    EXPECT_TRUE(o.covariance.isApprox(want.covariance, 1e-12));
    EXPECT_DOUBLE_EQ(o.forward_velocity_mps, 0.5);
    EXPECT_DOUBLE_EQ(o.yaw_rate_radps, 0.1);

    const core::WheelEncoderReading& w = got.wheels[i];
    EXPECT_NEAR(w.stamp_s, testing::LoopbackStamp(i), 1e-9);
    const double dl =
        i == 0 ? 0.0 : testing::LoopbackLeftWheel_rad(i) - testing::LoopbackLeftWheel_rad(i - 1);
    const double dr =
        i == 0 ? 0.0 : testing::LoopbackRightWheel_rad(i) - testing::LoopbackRightWheel_rad(i - 1);
    EXPECT_NEAR(w.left_delta_rad, dl, 1e-12);
    EXPECT_NEAR(w.right_delta_rad, dr, 1e-12);

    const core::LaserScan want_scan = testing::LoopbackScan(i);
    const core::LaserScan& s = got.scans[i];
    EXPECT_NEAR(s.stamp_s, want_scan.stamp_s, 1e-9);
    ASSERT_EQ(s.ranges_m.size(), want_scan.ranges_m.size());
    for (std::size_t k = 0; k < s.ranges_m.size(); ++k) {
      EXPECT_NEAR(s.ranges_m[k], want_scan.ranges_m[k], 1e-6) << "beam " << k;
    }
    EXPECT_FLOAT_EQ(static_cast<float>(s.angle_min_rad), -1.5f);
    EXPECT_FLOAT_EQ(static_cast<float>(s.angle_increment_rad), 0.5f);

    EXPECT_NEAR(got.images[i].first, testing::LoopbackStamp(i) + 0.02, 1e-9);
    EXPECT_EQ(cv::countNonZero(got.images[i].second != testing::LoopbackImage(i)), 0);
  }
  const DdsInputCounters& scans = inputs->counters(DdsInput::kScan);
  EXPECT_EQ(scans.received, static_cast<std::uint64_t>(n + 2));
  EXPECT_EQ(scans.dropped, 2u);
  // The stale scan came last, so its stamp is the last drop.
  EXPECT_NE(scans.last_drop_reason.find("sensor_msgs/LaserScan: field 'header.stamp'"),
            std::string::npos)
      << scans.last_drop_reason;
  const DdsInputCounters& odom = inputs->counters(DdsInput::kOdometry);
  EXPECT_EQ(odom.dropped, 1u);
  EXPECT_NE(odom.last_drop_reason.find("nav_msgs/Odometry: field 'pose.pose.position.x'"),
            std::string::npos)
      << odom.last_drop_reason;
  EXPECT_EQ(inputs->counters(DdsInput::kJointState).dropped, 0u);
  EXPECT_EQ(inputs->counters(DdsInput::kImage).dropped, 0u);
}

}  // namespace
}  // namespace groundline::io
