// `groundline replay-dds` end to end: the CLI, in its own process, replays a
// small synthetic dataset over loopback DDS; this process receives it through
// DdsInputs and checks every stream against the dataset: odometry equals the
// causal diff-drive integration of the wheel readings, joint-state
// increments equal the encoder deltas, scans equal the dataset's scans
// (stamped at their first ray).
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "../core/dataset_fixture.h"
#include "dds_test_env.h"
#include "groundline/core/dataset.h"
#include "groundline/io/dds_inputs.h"
#include "groundline/localization/lidar/scan_odometry.h"
#include "groundline/localization/odometry_integrator.h"
#include "test_data.h"
#include "tools_under_test.h"

extern char** environ;

namespace groundline::io {
namespace {

constexpr unsigned kReplayDomainId = 178;

TEST(DdsReplayTest, ReplayedStreamsEqualTheDataset) {
  testing::UseLoopbackConfig();
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("dataset");
  ASSERT_TRUE(core::WriteDataset(dir, ::groundline::testing::MakeSyntheticDataset(dir)).ok());
  // As written (ranges at 0.1 mm): what the replay reads.
  core::DatasetReadOptions read;
  read.check_image_files = false;
  const core::Result<core::Dataset> written = core::ReadDataset(dir, read);
  ASSERT_TRUE(written.ok()) << written.message();
  const core::Dataset& d = *written;

  DdsParticipantOptions po;
  po.domain_id = kReplayDomainId;
  core::Result<DdsParticipant> participant = DdsParticipant::Create(po);
  ASSERT_TRUE(participant.ok()) << participant.message();
  std::vector<PlanarOdometry> odom;
  std::vector<core::WheelEncoderReading> wheels;
  std::vector<core::LaserScan> scans;
  DdsInputCallbacks cb;
  cb.on_odometry = [&](const PlanarOdometry& o) { odom.push_back(o); };
  cb.on_wheels = [&](const core::WheelEncoderReading& w) { wheels.push_back(w); };
  cb.on_scan = [&](const core::LaserScan& s) { scans.push_back(s); };
  // A namespace of this process keeps parallel runs of this test apart.
  const std::string ns = "replay" + std::to_string(::getpid());
  DdsInputsOptions options;
  options.odometry_topic = "rt/" + ns + "/odom";
  options.joint_state_topic = "rt/" + ns + "/joint_states";
  options.scan_topic = "rt/" + ns + "/scan";
  options.image_topic.clear();
  options.initial_pose_topic.clear();
  options.sensor_qos = QosPreset::kLossless;
  options.stamp_reference = StampReference::kNewest;
  // At 20x, the window's 1 s of age is 50 ms of wall time: on a loaded
  // machine a topic delivered that much later than another (a retransmit on a
  // full socket buffer) would be rejected as stale. This test is about the
  // streams' content, not the window (dds_validate_test.cc checks that).
  options.stamp_window.max_stamp_age_s = 1e3;
  core::Result<DdsInputs> inputs = DdsInputs::Create(*participant, options, cb);
  ASSERT_TRUE(inputs.ok()) << inputs.message();

  const std::string exe = ::groundline::testing::GroundlineCli();
  std::vector<std::string> args = {exe,
                                   "replay-dds",
                                   dir.string(),
                                   "--rate",
                                   "20",
                                   "--stamps",
                                   "dataset",
                                   "--namespace",
                                   ns,
                                   "--lossless",
                                   "--wait-for-subscribers",
                                   "60"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string domain = "ROS_DOMAIN_ID=" + std::to_string(kReplayDomainId);
  std::vector<char*> env;
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::string(*e).rfind("ROS_DOMAIN_ID=", 0) != 0) env.push_back(*e);
  }
  env.push_back(const_cast<char*>(domain.c_str()));
  env.push_back(nullptr);
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), env.data()), 0);

  int status = 0;
  bool exited = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!exited && std::chrono::steady_clock::now() < deadline) {
    ASSERT_TRUE(inputs->Poll(std::chrono::milliseconds(100)).ok());
    exited = waitpid(pid, &status, WNOHANG) == pid;
  }
  if (!exited) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    FAIL() << "replay-dds did not finish";
  }
  // It exits once its writers are acknowledged: everything is in our history.
  ASSERT_TRUE(inputs->Poll(std::chrono::milliseconds(0)).ok());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "replay-dds failed";

  for (const DdsInput which : {DdsInput::kOdometry, DdsInput::kJointState, DdsInput::kScan}) {
    const DdsInputCounters& c = inputs->counters(which);
    EXPECT_EQ(c.dropped, 0u) << "topic " << static_cast<int>(which) << ": received " << c.received
                             << ", last drop: " << c.last_drop_reason;
  }
  ASSERT_EQ(odom.size(), d.wheel_encoders.size());
  ASSERT_EQ(wheels.size(), d.wheel_encoders.size());
  localization::DiffDriveParams drive;
  drive.wheel_radius_m = d.manifest.wheel_encoders->wheel_radius_m;
  drive.track_m = d.manifest.wheel_encoders->track_m;
  localization::OdometryIntegrator integrator(drive, localization::OdometryNoiseParams{});
  for (std::size_t i = 0; i < d.wheel_encoders.size(); ++i) {
    SCOPED_TRACE("reading " + std::to_string(i));
    const core::WheelEncoderReading& r = d.wheel_encoders[i];
    if (i > 0) integrator.Integrate({r.left_delta_rad, r.right_delta_rad});
    EXPECT_NEAR(odom[i].stamp_s, r.stamp_s, 1e-6);
    EXPECT_TRUE(odom[i].T_odom_base.IsApprox(integrator.T_odom_base(), 1e-9, 1e-9));
    EXPECT_TRUE(odom[i].covariance.isApprox(integrator.covariance(), 1e-9));
    EXPECT_NEAR(wheels[i].stamp_s, r.stamp_s, 1e-6);
    EXPECT_NEAR(wheels[i].left_delta_rad, i == 0 ? 0.0 : r.left_delta_rad, 1e-9);
    EXPECT_NEAR(wheels[i].right_delta_rad, i == 0 ? 0.0 : r.right_delta_rad, 1e-9);
  }
  ASSERT_EQ(scans.size(), d.scans.size());
  ASSERT_TRUE(d.manifest.lidar.has_value());
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    // ROS stamps a scan at its first ray; a mid-sweep dataset's is half a sweep later.
    const double sweep_s = localization::lidar::MidSweepOffsetS(
        d.scans[i].ranges_m.size(), d.scans[i].angle_increment_rad, d.manifest.lidar->rate_hz);
    const bool mid_sweep = d.manifest.lidar->stamp == core::LidarStamp::kMidSweep;
    EXPECT_NEAR(scans[i].stamp_s, d.scans[i].stamp_s - (mid_sweep ? sweep_s : 0.0), 1e-6)
        << "scan " << i;
    ASSERT_EQ(scans[i].ranges_m.size(), d.scans[i].ranges_m.size());
    for (std::size_t k = 0; k < scans[i].ranges_m.size(); ++k) {
      // float32 on the wire: 1e-7 relative.
      EXPECT_NEAR(scans[i].ranges_m[k], d.scans[i].ranges_m[k], 1e-5)
          << "scan " << i << " beam " << k;
    }
  }
  for (int i = 0; i < kNumDdsInputs; ++i) {
    EXPECT_EQ(inputs->counters(static_cast<DdsInput>(i)).dropped, 0u)
        << inputs->counters(static_cast<DdsInput>(i)).last_drop_reason;
  }
}

}  // namespace
}  // namespace groundline::io
