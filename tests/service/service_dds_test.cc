// The service on DDS end to end, with real CycloneDDS participants in three
// processes on loopback (the test's own domain id): `groundline replay-dds`
// publishes a short simulated zone B drive, `groundline serve` localizes on
// it (inputs.dds, output.dds) from a wrong start until this process's
// /initialpose re-initializes it, and service_dds_pose_listener receives the
// pose and map -> odom. Checked: the pose stream arrives whole and follows
// the re-initialization, its accuracy against the ground truth from then on
// is that of the file replay of the same dataset, nothing is lost (every
// published message accepted, every pose the service wrote received), and
// bad messages injected by this process are dropped and counted. Reliable
// keep-all QoS on both ends (inputs.dds.qos: lossless, replay-dds
// --lossless), so that a loaded machine slows the chain down instead of
// losing data: nothing here depends on timing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "../io/dds_test_env.h"
#include "child_process.h"
#include "groundline/core/trajectory_association.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_pubsub.h"
#include "groundline/service/service.h"
#include "groundline/service/service_config.h"
#include "simulated_drive.h"
#include "test_data.h"
#include "tools_under_test.h"

extern char** environ;

namespace groundline::service {
namespace {

constexpr unsigned kDomainId = 179;

using ::groundline::testing::ReadText;

// A child process with stdout and stderr in a file, on the test's domain.
class Child : public testing::ChildProcess {
 public:
  Child(std::vector<std::string> args, const std::filesystem::path& log)
      : ChildProcess(std::move(args), log, {}, {"ROS_DOMAIN_ID=" + std::to_string(kDomainId)}) {}
};

// ATE RMSE [m] of the estimate against the ground truth, interpolated at its stamps.
double AteRmse(const core::Trajectory& estimate, const core::Trajectory& truth) {
  double sum = 0.0;
  for (const core::StampedPose& p : estimate) {
    sum += (p.pose.translation() - core::InterpolatePose(truth, p.stamp_s).translation())
               .squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(estimate.size()));
}

TEST(ServiceDds,
     ReplayToServeToListenerFollowsAReinitializationMatchesTheFileReplayAndLosesNothing) {
  io::testing::UseLoopbackConfig();
  // Scan matching under AddressSanitizer is several times slower: a shorter drive.
  const double length_m = ::groundline::testing::Sanitized() ? 12.0 : 20.0;
  const std::string preset = "fusion";
  const auto dir = ::groundline::testing::ScratchDir("service_dds");
  const std::optional<sim::SimRun> simulated =
      testing::SimulatedZoneBDrive(length_m, 7, dir / "drive");
  ASSERT_TRUE(simulated.has_value());
  const core::Trajectory& truth = simulated->dataset.ground_truth;

  // The file replay of the same dataset, as fast as possible.
  ServiceConfig file;
  file.replay_dataset = (dir / "drive").string();
  file.replay_speed = 0.0;
  file.preset = preset;
  file.output_dir = (dir / "file").string();
  file.http_enabled = false;
  file.resume = false;
  {
    core::Result<std::unique_ptr<Service>> service = Service::Create(file);
    ASSERT_TRUE(service.ok()) << service.message();
    std::atomic<bool> never{false};
    ASSERT_TRUE((*service)->Run(never).ok());
  }
  const core::Result<core::Trajectory> file_poses =
      core::ReadTumTrajectory(dir / "file" / "trajectory.tum");
  ASSERT_TRUE(file_poses.ok()) << file_poses.message();

  // The DDS chain. Topics under a namespace of this process. The service
  // starts 1.5 m and 10 deg off the true start; an /initialpose from this
  // process, stamped 1.5 s into the drive, puts it back on the truth.
  const std::string ns = "gl" + std::to_string(::getpid());
  const double deg = std::numbers::pi / 180.0;
  const core::SE2 wrong_start =
      core::InterpolatePose(truth, simulated->dataset.wheel_encoders.front().stamp_s) *
      core::SE2(1.5, 0.0, 10.0 * deg);
  std::ofstream(dir / "serve.yaml")
      << "inputs:\n"
      << "  replay: {dataset: drive}\n"
      << "  dds: {odometry: odom, scan: true, image: false, "
         "initial_pose: true, namespace: "
      << ns << ", stamp_check: none, qos: lossless}\n"
      << "localizer: {preset: " << preset << "}\n"
      << "start: {resume: false, initial_pose: [" << wrong_start.x() << ", " << wrong_start.y()
      << ", " << wrong_start.yaw() / deg << "]}\n"
      << "output:\n  dir: dds\n  dds: {namespace: " << ns << "}\n"
      << "http: {enabled: false}\n";
  Child serve(
      {::groundline::testing::GroundlineCli(), "serve", "--config", (dir / "serve.yaml").string()},
      dir / "serve.log");
  ASSERT_TRUE(serve.started());
  Child listener({GROUNDLINE_DDS_POSE_LISTENER, "--out", (dir / "listened.tum").string(),
                  "--prefix", "rt/" + ns + "/"},
                 dir / "listener.log");
  ASSERT_TRUE(listener.started());
  // The listener sees the service's writers: the service is up.
  ASSERT_TRUE(listener.WaitForOutput("listener: matched", std::chrono::seconds(120)))
      << listener.output() << serve.output();

  // Bad messages from this process on the service's own input topics.
  io::DdsParticipantOptions po;
  po.domain_id = kDomainId;
  core::Result<io::DdsParticipant> participant = io::DdsParticipant::Create(po);
  ASSERT_TRUE(participant.ok()) << participant.message();
  auto bad_odom = io::DdsPublisher<io::RosOdometry>::Create(*participant, "rt/" + ns + "/odom",
                                                            io::QosPreset::kLossless);
  auto bad_scan = io::DdsPublisher<io::RosLaserScan>::Create(*participant, "rt/" + ns + "/scan",
                                                             io::QosPreset::kLossless);
  ASSERT_TRUE(bad_odom.ok() && bad_scan.ok());
  ASSERT_TRUE(io::WaitForMatches(bad_odom->writer(), true, 1, std::chrono::seconds(60)));
  ASSERT_TRUE(io::WaitForMatches(bad_scan->writer(), true, 1, std::chrono::seconds(60)));
  // RViz's "2D Pose Estimate" with the true pose, sent before the drive is
  // published: the localizer holds it (1.5 s ahead of its start, within
  // max_sensor_lead_s) until the odometry reaches its stamp, so that where
  // it applies does not depend on timing.
  auto rviz = io::DdsPublisher<io::RosPoseWithCovarianceStamped>::Create(
      *participant, "rt/" + ns + "/initialpose", io::QosPreset::kDefault);
  ASSERT_TRUE(rviz.ok());
  ASSERT_TRUE(io::WaitForMatches(rviz->writer(), true, 1, std::chrono::seconds(60)));
  io::PlanarPoseStamped put_back;
  put_back.stamp_s = simulated->dataset.wheel_encoders.front().stamp_s + 1.5;
  put_back.frame_id = "map";
  put_back.T_frame_base = core::InterpolatePose(truth, put_back.stamp_s);
  put_back.covariance = core::Vector3(1e-4, 1e-4, 1e-4).asDiagonal();
  ASSERT_TRUE(rviz->Write(io::ToPoseWithCovarianceStamped(put_back).msg()).ok());
  dds_wait_for_acks(rviz->writer().get(), DDS_SECS(10));

  Child replay({::groundline::testing::GroundlineCli(), "replay-dds", (dir / "drive").string(),
                "--rate", "4", "--stamps", "dataset", "--odometry", "odom", "--namespace", ns,
                "--lossless", "--wait-for-subscribers", "120"},
               dir / "replay.log");
  ASSERT_TRUE(replay.started());
  // Mid-drive: a wrong child frame and a scan whose ranges disagree with its angles.
  ASSERT_TRUE(replay.WaitForOutput("on DDS domain", std::chrono::seconds(120)));
  constexpr int kBad = 3;
  const double mid_s = simulated->dataset.wheel_encoders[200].stamp_s;
  for (int i = 0; i < kBad; ++i) {
    io::PlanarOdometry odom;
    odom.stamp_s = mid_s + 0.001 * i;
    odom.base_frame = "wrong_frame";
    ASSERT_TRUE(bad_odom->Write(io::ToOdometry(odom).msg()).ok());
    core::LaserScan scan = simulated->dataset.scans[10];
    scan.stamp_s = mid_s + 0.001 * i;
    io::DdsSample<io::RosLaserScan> msg = io::ToLaserScan(scan, "laser");
    msg.msg().angle_max += 10.0f * msg.msg().angle_increment;  // 10 beams more than ranges
    ASSERT_TRUE(bad_scan->Write(msg.msg()).ok());
  }
  ASSERT_EQ(replay.Wait(std::chrono::seconds(600)), 0) << replay.output();
  dds_wait_for_acks(bad_odom->writer().get(), DDS_SECS(10));
  dds_wait_for_acks(bad_scan->writer().get(), DDS_SECS(10));

  // Everything published is in the service's readers: stop it; it takes
  // them, drains its queues, and waits for the listener's acknowledgements.
  serve.Terminate();
  ASSERT_EQ(serve.Wait(std::chrono::seconds(600)), 0) << serve.output();
  listener.Terminate();
  ASSERT_EQ(listener.Wait(std::chrono::seconds(60)), 0) << listener.output();

  std::smatch published;
  const std::string replay_log = replay.output();
  ASSERT_TRUE(std::regex_search(replay_log, published,
                                std::regex("published (\\d+) wheel readings, (\\d+) scans")))
      << replay_log;
  const long wheels = std::stol(published[1]), scans = std::stol(published[2]);
  EXPECT_EQ(static_cast<std::size_t>(wheels), simulated->dataset.wheel_encoders.size());

  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "dds" / "summary.json"));
  const nlohmann::json& in = summary["dds"]["inputs"];
  EXPECT_EQ(in["odometry"]["received"].get<long>(), wheels + kBad);
  EXPECT_EQ(in["odometry"]["accepted"].get<long>(), wheels);
  EXPECT_EQ(in["odometry"]["dropped"].get<long>(), kBad);
  EXPECT_NE(in["odometry"]["last_drop_reason"].get<std::string>().find("child_frame_id"),
            std::string::npos)
      << in["odometry"]["last_drop_reason"];
  EXPECT_EQ(in["scan"]["received"].get<long>(), scans + kBad);
  EXPECT_EQ(in["scan"]["accepted"].get<long>(), scans);
  EXPECT_EQ(in["scan"]["dropped"].get<long>(), kBad);
  EXPECT_NE(in["scan"]["last_drop_reason"].get<std::string>().find("ranges"), std::string::npos)
      << in["scan"]["last_drop_reason"];
  // The estimator took every accepted reading, and the re-initialization.
  EXPECT_EQ(summary["counters"]["wheel_readings"].get<long>(), wheels);
  EXPECT_EQ(summary["counters"]["wheel_dropped_out_of_order"].get<long>(), 0);
  EXPECT_EQ(summary["dds"]["initial_poses"]["applied"].get<long>(), 1);
  EXPECT_EQ(summary["dds"]["initial_poses"]["refused"].get<long>(), 0);
  EXPECT_EQ(summary["counters"]["reinitializations"].get<long>(), 1);

  // Every pose the service wrote arrived, and each keyframe was written.
  const nlohmann::json& out = summary["dds"]["outputs"];
  const core::Result<core::Trajectory> listened = core::ReadTumTrajectory(dir / "listened.tum");
  ASSERT_TRUE(listened.ok()) << listened.message();
  EXPECT_EQ(static_cast<long>(listened->size()), out["poses"].get<long>());
  EXPECT_EQ(out["poses"].get<long>(), summary["counters"]["keyframes"].get<long>());
  EXPECT_EQ(out["write_errors"].get<long>(), 0);
  std::smatch received;
  const std::string listener_log = listener.output();
  ASSERT_TRUE(std::regex_search(listener_log, received, std::regex("poses (\\d+) tf (\\d+)")));
  EXPECT_EQ(std::stol(received[2]), out["tf"].get<long>());
  EXPECT_GT(out["tf"].get<long>(), wheels / 2);

  // Before the re-initialization the published poses are the wrong start's;
  // from it on, the accuracy of the file replay (which started on the
  // truth): ATE within 5 mm of it (float32 ranges, first-ray stamps
  // converted back to mid-sweep, arrival order across topics, the restart).
  const auto split = [&](const core::Trajectory& poses, bool after) {
    core::Trajectory part;
    for (const core::StampedPose& p : poses) {
      if ((p.stamp_s >= put_back.stamp_s) == after) part.push_back(p);
    }
    return part;
  };
  const core::Trajectory before = split(*listened, false);
  const core::Trajectory after = split(*listened, true);
  ASSERT_GE(before.size(), 2u);
  ASSERT_GT(after.size(), 10u);
  double least_before_m = std::numeric_limits<double>::infinity();
  for (const core::StampedPose& p : before) {
    least_before_m = std::min(least_before_m, AteRmse({p}, truth));
  }
  EXPECT_GT(least_before_m, 0.5);
  const double ate_dds_m = AteRmse(after, truth);
  const double ate_file_m = AteRmse(split(*file_poses, true), truth);
  EXPECT_NEAR(ate_dds_m, ate_file_m, 0.005) << "DDS " << ate_dds_m << " m, file " << ate_file_m;
  EXPECT_LT(ate_dds_m, 0.05);
  EXPECT_NEAR(static_cast<double>(listened->size()), static_cast<double>(file_poses->size()),
              0.05 * static_cast<double>(file_poses->size()));
  std::printf(
      "ATE RMSE after the re-initialization: DDS chain %.4f m (%zu poses), file replay %.4f m "
      "(%zu poses); before it the DDS poses are >= %.3f m off\n",
      ate_dds_m, after.size(), ate_file_m, file_poses->size(), least_before_m);
}

// The service's own process on DDS: joint states in, started by an
// rt/initialpose and moved mid-run by another (one stamped on another clock
// refused and counted), the pose, map -> odom and diagnostics out to this
// process.
TEST(ServiceDds, StartsAndReinitializesFromTheInitialPoseTopicAndPublishesPoseTfAndDiagnostics) {
  io::testing::UseLoopbackConfig();
  ::setenv("ROS_DOMAIN_ID", std::to_string(kDomainId).c_str(), 1);
  const auto dir = ::groundline::testing::ScratchDir("service_dds_start");
  ASSERT_TRUE(testing::SimulatedZoneBDrive(4.0, 3, dir / "drive").has_value());
  const std::string ns = "gls" + std::to_string(::getpid());
  std::ofstream(dir / "serve.yaml")
      << "inputs:\n  replay: {dataset: drive}\n"
      << "  dds: {odometry: joint_states, scan: false, namespace: " << ns
      << ", stamp_check: none, qos: lossless}\n"
      << "localizer: {preset: odometry}\n"
      << "start: {resume: false, wait_for_initial_pose: true}\n"
      << "output:\n  dir: out\n  dds: {namespace: " << ns << ", diagnostics_period_s: 0.1}\n"
      << "http: {enabled: false}\n";
  core::Result<ServiceConfig> config = ReadServiceConfig(dir / "serve.yaml");
  ASSERT_TRUE(config.ok()) << config.message();
  core::Result<std::unique_ptr<Service>> service = Service::Create(*config);
  ASSERT_TRUE(service.ok()) << service.message();
  std::atomic<bool> stop{false};
  core::Result<nlohmann::ordered_json> summary = core::Status::Error("not run");
  std::thread run([&] { summary = (*service)->Run(stop); });

  core::Result<io::DdsParticipant> participant = io::DdsParticipant::Create();
  ASSERT_TRUE(participant.ok()) << participant.message();
  const std::string prefix = "rt/" + ns + "/";
  auto joints = io::DdsPublisher<io::RosJointState>::Create(*participant, prefix + "joint_states",
                                                            io::QosPreset::kLossless);
  auto initial = io::DdsPublisher<io::RosPoseWithCovarianceStamped>::Create(
      *participant, prefix + "initialpose", io::QosPreset::kDefault);
  auto pose = io::DdsSubscriber<io::RosPoseWithCovarianceStamped>::Create(
      *participant, prefix + "groundline/pose", io::QosPreset::kPoseOutput);
  auto tf = io::DdsSubscriber<io::RosTfMessage>::Create(*participant, prefix + "tf",
                                                        io::QosPreset::kLossless);
  auto diagnostics = io::DdsSubscriber<io::RosDiagnosticArray>::Create(
      *participant, prefix + "diagnostics", io::QosPreset::kDefault);
  ASSERT_TRUE(joints.ok() && initial.ok() && pose.ok() && tf.ok() && diagnostics.ok());
  for (const io::DdsEntity* w : {&joints->writer(), &initial->writer()}) {
    ASSERT_TRUE(io::WaitForMatches(*w, true, 1, std::chrono::seconds(60)));
  }
  for (const io::DdsEntity* r : {&pose->reader(), &tf->reader(), &diagnostics->reader()}) {
    ASSERT_TRUE(io::WaitForMatches(*r, false, 1, std::chrono::seconds(60)));
  }
  const auto status_until = [&](const std::function<bool(const nlohmann::ordered_json&)>& done) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < deadline) {
      if (done((*service)->StatusJson())) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  };
  // Straight at 1 m/s: 1 cm of both wheels per 10 ms.
  const double radius_m = 0.125;  // the simulated vehicle's
  constexpr double kT0 = 1000.0;
  const auto publish_readings = [&](int from, int to) {
    for (int k = from; k < to; ++k) {
      io::WheelJointState js;
      js.stamp_s = kT0 + 0.01 * k;
      js.names = {"left_wheel_joint", "right_wheel_joint"};
      js.position_rad = {0.01 * k / radius_m, 0.01 * k / radius_m};
      ASSERT_TRUE(joints->Write(io::ToJointState(js).msg()).ok());
    }
  };
  const auto readings_taken = [](long n) {
    return [n](const nlohmann::ordered_json& j) {
      return j["counters"]["wheel_readings"].get<long>() >= n;
    };
  };
  publish_readings(0, 51);
  ASSERT_TRUE(status_until(readings_taken(51)));
  EXPECT_FALSE((*service)->StatusJson()["started"].get<bool>());
  io::PlanarPoseStamped start;
  start.stamp_s = kT0 + 0.505;
  start.frame_id = "map";
  start.T_frame_base = core::SE2(2.0, 3.0, std::numbers::pi / 2);
  start.covariance = core::Vector3(0.01, 0.01, 0.001).asDiagonal();
  ASSERT_TRUE(initial->Write(io::ToPoseWithCovarianceStamped(start).msg()).ok());
  ASSERT_TRUE(status_until([](const nlohmann::ordered_json& j) {
    return j["dds"]["initial_poses"]["applied"].get<long>() == 1;
  }));
  publish_readings(51, 150);
  ASSERT_TRUE(status_until(readings_taken(150)));
  // Mid-run: one stamped 100 s ahead of the odometry (another clock) is
  // refused and counted; then RViz's "2D Pose Estimate" moves the running
  // estimate: the pose at 1.45 s, carried by the wheels to the newest
  // reading (1.49 s).
  start.stamp_s = kT0 + 100.0;
  ASSERT_TRUE(initial->Write(io::ToPoseWithCovarianceStamped(start).msg()).ok());
  ASSERT_TRUE(status_until([](const nlohmann::ordered_json& j) {
    return j["dds"]["initial_poses"]["refused"].get<long>() == 1;
  }));
  io::PlanarPoseStamped moved = start;
  moved.stamp_s = kT0 + 1.45;
  moved.T_frame_base = core::SE2(5.0, -1.0, 0.0);
  ASSERT_TRUE(initial->Write(io::ToPoseWithCovarianceStamped(moved).msg()).ok());
  ASSERT_TRUE(status_until([](const nlohmann::ordered_json& j) {
    return j["dds"]["initial_poses"]["applied"].get<long>() == 2;
  }));
  const nlohmann::ordered_json reinitialized = (*service)->StatusJson();
  EXPECT_NEAR(reinitialized["pose"]["x_m"].get<double>(), 5.04, 1e-6);
  EXPECT_NEAR(reinitialized["pose"]["y_m"].get<double>(), -1.0, 1e-6);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // a diagnostics period or two
  publish_readings(150, 200);
  ASSERT_TRUE(status_until(readings_taken(200)));
  stop.store(true);
  run.join();
  ASSERT_TRUE(summary.ok()) << summary.message();

  // From the given pose 0.54 m along its heading (1.45 s to 1.99 s).
  const nlohmann::ordered_json& end = *summary;
  EXPECT_NEAR(end["pose"]["x_m"].get<double>(), 5.0 + 0.54, 1e-6);
  EXPECT_NEAR(end["pose"]["y_m"].get<double>(), -1.0, 1e-6);
  EXPECT_NEAR(end["pose"]["yaw_deg"].get<double>(), 0.0, 1e-6);
  EXPECT_EQ(end["counters"]["wheel_before_start"].get<long>(), 51);
  EXPECT_EQ(end["counters"]["reinitializations"].get<long>(), 1);
  EXPECT_EQ(end["counters"]["initial_poses_dropped_ahead"].get<long>(), 1);
  EXPECT_NE(end["dds"]["initial_poses"]["last_error"].get<std::string>().find("max_sensor_lead_s"),
            std::string::npos)
      << end["dds"]["initial_poses"]["last_error"];

  // The outputs arrived: keyframe poses that follow the re-initialization,
  // map -> odom consistent with the service's own odometry frame (the joint
  // states integrated from the first, 1.99 m straight), diagnostics naming
  // the localizer and its re-initialization.
  std::vector<io::PlanarPoseStamped> poses;
  ASSERT_TRUE(pose->Take([&](const io::RosPoseWithCovarianceStamped& m) {
                    poses.push_back(io::FromPoseWithCovarianceStamped(m));
                  })
                  .ok());
  ASSERT_FALSE(poses.empty());  // transient local, depth 1: at least the last
  EXPECT_GT(poses.back().stamp_s, kT0 + 1.49);
  EXPECT_GT(poses.back().T_frame_base.x(), 5.2);
  EXPECT_NEAR(poses.back().T_frame_base.y(), -1.0, 1e-6);
  EXPECT_NEAR(poses.back().T_frame_base.yaw(), 0.0, 1e-6);
  core::SE2 T_map_odom;
  int transforms = 0;
  ASSERT_TRUE(tf->Take([&](const io::RosTfMessage& m) {
                  for (std::uint32_t i = 0; i < m.transforms._length; ++i) {
                    const auto& t = m.transforms._buffer[i];
                    EXPECT_STREQ(t.header.frame_id, "map");
                    EXPECT_STREQ(t.child_frame_id, "odom");
                    const auto& q = t.transform.rotation;
                    T_map_odom = core::SE2(t.transform.translation.x, t.transform.translation.y,
                                           2.0 * std::atan2(q.z, q.w));
                    ++transforms;
                  }
                }).ok());
  EXPECT_EQ(transforms, end["dds"]["outputs"]["tf"].get<int>());
  EXPECT_EQ(transforms, 200 - 51);  // one per reading after the start
  const core::SE2 T_odom_base(1.99, 0.0, 0.0);
  EXPECT_TRUE((T_map_odom * T_odom_base).IsApprox(core::SE2(5.54, -1.0, 0.0), 1e-6, 1e-6));
  bool localizer_seen = false, reinitialization_seen = false;
  ASSERT_TRUE(diagnostics
                  ->Take([&](const io::RosDiagnosticArray& m) {
                    for (std::uint32_t i = 0; i < m.status._length; ++i) {
                      const auto& status = m.status._buffer[i];
                      if (std::string(status.name) != "groundline: localizer") continue;
                      localizer_seen = true;
                      for (std::uint32_t v = 0; v < status.values._length; ++v) {
                        if (std::string(status.values._buffer[v].key) == "reinitializations" &&
                            std::string(status.values._buffer[v].value) == "1") {
                          reinitialization_seen = true;
                        }
                      }
                    }
                  })
                  .ok());
  EXPECT_TRUE(localizer_seen);
  EXPECT_TRUE(reinitialization_seen);
}

}  // namespace
}  // namespace groundline::service
