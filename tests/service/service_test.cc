// `groundline serve`'s library (service/service.h): config errors that name
// the key and line, a replay through the threaded stages with the HTTP
// health endpoint, and a stop that saves the state a restart resumes from.
#include "groundline/service/service.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <memory>
#include <numbers>
#include <thread>
#include <vector>

#include <Eigen/Cholesky>

#include "groundline/calibration/mount_estimate_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/trajectory_association.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/odometry_calibration.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/service/service_config.h"
#include "groundline/service/service_state.h"
#include "groundline/sim/sim_run.h"
#include "simulated_drive.h"
#include "test_data.h"
#include "tools_under_test.h"

// Last: <resolv.h>, which it includes, defines the macro _res that Eigen uses as a name.
#include <httplib.h>

namespace groundline::service {
namespace {

std::filesystem::path WriteConfig(const std::filesystem::path& dir, const std::string& text) {
  std::filesystem::create_directories(dir);
  const auto path = dir / "serve.yaml";
  std::ofstream(path) << text;
  return path;
}

// The service replaying dataset_dir as fast as possible into out_dir, fresh
// (no resume), without its HTTP endpoint, with the given injected faults.
core::Result<nlohmann::ordered_json> ReplayAsFastAsPossible(
    const std::filesystem::path& dataset_dir, const std::filesystem::path& out_dir,
    std::vector<InjectedFault> faults = {}) {
  ServiceConfig config;
  config.replay_dataset = dataset_dir.string();
  config.replay_speed = 0.0;
  config.output_dir = out_dir.string();
  config.http_enabled = false;
  config.resume = false;
  config.faults = std::move(faults);
  core::Result<std::unique_ptr<Service>> created = Service::Create(config);
  if (!created.ok()) return created.status();
  std::atomic<bool> never{false};
  return (*created)->Run(never);
}

TEST(ServiceConfig, ErrorsNameTheKeyAndTheLine) {
  const auto dir = ::groundline::testing::ScratchDir("service_config");
  struct Case {
    const char* text;
    const char* expected;
  } cases[] = {
      {"inputs:\n  replay: {dataset: d, sped: 2}\noutput: {dir: o}\n", "sped"},
      {"inputs:\n  replay: {dataset: d, speed: -1}\noutput: {dir: o}\n", "inputs.replay.speed"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nlocalizer: {preset: magic}\n",
       "localizer.preset"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nhttp: {port: 70000}\n", "http.port"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nstart: {initial_pose: [1, 2]}\n",
       "start.initial_pose"},
      {"inputs:\n  replay: {dataset: d}\n", "output"},
      {"inputs:\n  replay: {dataset: d}\n  dds: {odometry: wheels}\noutput: {dir: o}\n",
       "inputs.dds.odometry"},
      {"inputs:\n  replay: {dataset: d}\n  dds: {qos: fast}\noutput: {dir: o}\n", "inputs.dds.qos"},
      {"inputs:\n  replay: {dataset: d}\n  dds: {stamp_check: later}\noutput: {dir: o}\n",
       "inputs.dds.stamp_check"},
      {"inputs:\n  replay: {dataset: d}\n  dds: {topics: x}\noutput: {dir: o}\n", "topics"},
      {"inputs:\n  replay: {dataset: d}\n  dds: {namespace: /agv7}\noutput: {dir: o}\n",
       "inputs.dds.namespace"},
      {"inputs:\n  replay: {dataset: d}\n  dds: {scan: yes please}\noutput: {dir: o}\n",
       "inputs.dds.scan"},
      {"inputs:\n  replay: {dataset: d}\noutput:\n  dir: o\n  dds: {transform_tolerance_s: 5}\n",
       "output.dds.transform_tolerance_s"},
      {"inputs:\n  replay: {dataset: d}\noutput:\n  dir: o\n  dds: {pose: maybe}\n",
       "output.dds.pose"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nstart: {wait_for_initial_pose: true}\n",
       "start.wait_for_initial_pose"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nlocalizer: {self_calibration: maybe}\n",
       "localizer.self_calibration"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\n"
       "localizer: {preset: odometry, self_calibration: true}\n",
       "localizer.self_calibration: needs the camera's lines"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nlocalizer: {keep_atlas_current: 1x}\n",
       "localizer.keep_atlas_current"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\n"
       "localizer: {preset: lidar, keep_atlas_current: true}\n",
       "localizer.keep_atlas_current: needs an atlas"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nlocalizer: {bev: {x_m: [2, 1]}}\n",
       "localizer.bev: BEV extent x_m"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nlocalizer: {bev: {y_m: [1]}}\n",
       "localizer.bev.y_m"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nlocalizer: {bev: {cell: 1}}\n", "cell"},
      {"inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nlocalizer: {bev: {cell_m: 0}}\n",
       "localizer.bev: BEV extent cell_m"},
  };
  for (const Case& c : cases) {
    const core::Result<ServiceConfig> read = ReadServiceConfig(WriteConfig(dir, c.text));
    ASSERT_FALSE(read.ok()) << c.text;
    EXPECT_NE(read.message().find(c.expected), std::string::npos) << read.message();
    EXPECT_NE(read.message().find("serve.yaml"), std::string::npos) << read.message();
  }
  const core::Result<ServiceConfig> line = ReadServiceConfig(WriteConfig(
      dir, "inputs:\n  replay: {dataset: d}\noutput: {dir: o}\nqueues:\n  camera: x\n"));
  ASSERT_FALSE(line.ok());
  EXPECT_NE(line.message().find(":5:"), std::string::npos) << line.message();
  // A valid one: paths relative to the config file.
  const core::Result<ServiceConfig> ok = ReadServiceConfig(
      WriteConfig(dir, "inputs:\n  replay: {dataset: d, speed: 0}\noutput: {dir: o}\n"));
  ASSERT_TRUE(ok.ok()) << ok.message();
  EXPECT_EQ(ok->replay_dataset, (dir / "d").string());
  EXPECT_EQ(ok->http_address, "127.0.0.1");
  EXPECT_FALSE(ok->dds_inputs.enabled);
  EXPECT_FALSE(ok->dds_outputs.enabled);
  EXPECT_FALSE(ok->bev_x_m.has_value());  // the BEV: the camera's footprint
  EXPECT_EQ(ok->bev_cell_m, 0.01);
  const core::Result<ServiceConfig> bev =
      ReadServiceConfig(WriteConfig(dir,
                                    "inputs:\n  replay: {dataset: d}\noutput: {dir: o}\n"
                                    "localizer: {bev: {x_m: [0.7, 2.1], cell_m: 0.02}}\n"));
  ASSERT_TRUE(bev.ok()) << bev.message();
  ASSERT_TRUE(bev->bev_x_m.has_value());
  EXPECT_EQ((*bev->bev_x_m)[0], 0.7);
  EXPECT_EQ((*bev->bev_x_m)[1], 2.1);
  EXPECT_FALSE(bev->bev_y_m.has_value());
  EXPECT_EQ(bev->Bev().cell_m, 0.02);
  // The odometry calibration: a path relative to the config file.
  const core::Result<ServiceConfig> odometry =
      ReadServiceConfig(WriteConfig(dir,
                                    "inputs:\n  replay: {dataset: d}\noutput: {dir: o}\n"
                                    "localizer: {odometry_calibration: odometry.json}\n"));
  ASSERT_TRUE(odometry.ok()) << odometry.message();
  EXPECT_EQ(odometry->odometry_calibration, (dir / "odometry.json").string());
  // DDS: the line of a bad value, and the keys as read.
  const core::Result<ServiceConfig> bad_line =
      ReadServiceConfig(WriteConfig(dir,
                                    "inputs:\n  replay: {dataset: d}\n  dds:\n    odometry: odom\n"
                                    "    qos: fast\noutput: {dir: o}\n"));
  ASSERT_FALSE(bad_line.ok());
  EXPECT_NE(bad_line.message().find(":5:"), std::string::npos) << bad_line.message();
  const core::Result<ServiceConfig> dds = ReadServiceConfig(WriteConfig(
      dir,
      "inputs:\n  replay: {dataset: d}\n  dds: {odometry: joint_states, image: true, namespace: "
      "agv7, stamp_check: newest, qos: lossless}\noutput:\n  dir: o\n  dds: {tf: false, "
      "map_frame: world}\nstart: {wait_for_initial_pose: true}\n"));
  ASSERT_TRUE(dds.ok()) << dds.message();
  EXPECT_TRUE(dds->dds_inputs.enabled);
  EXPECT_EQ(dds->dds_inputs.odometry, "joint_states");
  EXPECT_TRUE(dds->dds_inputs.image);
  EXPECT_TRUE(dds->dds_inputs.scan);
  EXPECT_EQ(dds->dds_inputs.ros_namespace, "agv7");
  EXPECT_EQ(dds->dds_inputs.stamp_check, "newest");
  EXPECT_EQ(dds->dds_inputs.qos, "lossless");
  EXPECT_TRUE(dds->dds_outputs.enabled);
  EXPECT_FALSE(dds->dds_outputs.tf);
  EXPECT_TRUE(dds->dds_outputs.pose);
  EXPECT_EQ(dds->dds_outputs.map_frame, "world");
  EXPECT_DOUBLE_EQ(dds->dds_outputs.transform_tolerance_s, 0.1);
  EXPECT_TRUE(dds->wait_for_initial_pose);
  // `dds:` alone: every default.
  const core::Result<ServiceConfig> bare = ReadServiceConfig(
      WriteConfig(dir, "inputs:\n  replay: {dataset: d}\n  dds:\noutput: {dir: o}\n"));
  ASSERT_TRUE(bare.ok()) << bare.message();
  EXPECT_TRUE(bare->dds_inputs.enabled);
  EXPECT_EQ(bare->dds_inputs.odometry, "odom");
  EXPECT_EQ(bare->dds_inputs.qos, "sensor_data");
}

TEST(ServiceConfig, TheSampleConfigsAreValid) {
  for (const char* name : {"serve_replay.yaml", "serve_dds.yaml"}) {
    const core::Result<ServiceConfig> read =
        ReadServiceConfig(std::filesystem::path(GROUNDLINE_SAMPLES_DIR) / "config" / name);
    EXPECT_TRUE(read.ok()) << name << ": " << read.message();
  }
  const core::Result<ServiceConfig> dds = ReadServiceConfig(
      std::filesystem::path(GROUNDLINE_SAMPLES_DIR) / "config" / "serve_dds.yaml");
  ASSERT_TRUE(dds.ok());
  EXPECT_TRUE(dds->dds_inputs.enabled && dds->dds_outputs.enabled);
  EXPECT_EQ(dds->dds_inputs.qos, "sensor_data");
}

TEST(ServiceState, RoundTripsExactlyAndADamagedFileNamesTheField) {
  const auto dir = ::groundline::testing::ScratchDir("service_state");
  SavedState state;
  state.stamp_s = 1234.0625;
  state.T_map_base = core::SE2(10.1, -3.3, 2.5);
  state.covariance << 4e-4, 1e-5, 0, 1e-5, 3e-4, 2e-6, 0, 2e-6, 1e-5;
  ASSERT_TRUE(WriteServiceState(dir / "state.json", state).ok());
  const core::Result<SavedState> again = ReadServiceState(dir / "state.json");
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_EQ(again->stamp_s, state.stamp_s);
  EXPECT_EQ(again->T_map_base.x(), state.T_map_base.x());
  EXPECT_EQ(again->T_map_base.yaw(), state.T_map_base.yaw());
  EXPECT_EQ(again->covariance, state.covariance);

  struct Case {
    const char* text;
    const char* expected;  // in the message
  } cases[] = {
      {"{\"stamp_s\": 1, \"x_m\": 0, \"y_m\": 0, \"yaw_rad\": 0, \"cov\": [1, 0, 0",
       "not valid JSON"},
      {"", "not valid JSON"},
      {"[1, 2, 3]", "field 'stamp_s'"},
      {"{\"stamp_s\": \"1\", \"x_m\": 0, \"y_m\": 0, \"yaw_rad\": 0, \"cov\": []}",
       "field 'stamp_s': expected a number"},
      {"{\"stamp_s\": 1, \"y_m\": 0, \"yaw_rad\": 0, \"cov\": []}", "field 'x_m'"},
      {"{\"stamp_s\": 1, \"x_m\": 0, \"y_m\": 0, \"yaw_rad\": 0, \"cov\": [1, 0, 0]}",
       "field 'cov': expected an array of 9 numbers"},
      {"{\"stamp_s\": 1, \"x_m\": 0, \"y_m\": 0, \"yaw_rad\": 0, "
       "\"cov\": [1, 0, 0, 0, -1, 0, 0, 0, 1]}",
       "field 'cov': expected a symmetric positive definite"},
  };
  for (const Case& c : cases) {
    std::ofstream(dir / "bad.json") << c.text;
    const core::Result<SavedState> bad = ReadServiceState(dir / "bad.json");
    ASSERT_FALSE(bad.ok()) << c.text;
    EXPECT_NE(bad.message().find("bad.json"), std::string::npos) << bad.message();
    EXPECT_NE(bad.message().find(c.expected), std::string::npos) << bad.message();
    EXPECT_NE(bad.message().find("start.resume: false"), std::string::npos) << bad.message();
  }
}

TEST(Service, StopsOnRequestSavesItsStateAndResumesToTheEnd) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP()
        << "minutes of Debug scan matching under AddressSanitizer; runs in the release build";
  }
  const auto dir = ::groundline::testing::ScratchDir("service_run");
  const std::optional<sim::SimRun> simulated = testing::SimulatedZoneBDrive(20.0, 7, dir / "drive");
  ASSERT_TRUE(simulated.has_value());
  const double end_s = simulated->dataset.wheel_encoders.back().stamp_s;

  ServiceConfig config;
  config.replay_dataset = (dir / "drive").string();
  config.replay_speed = 4.0;  // paced: the stop lands mid-drive
  config.output_dir = (dir / "out").string();
  config.http_port = 0;
  core::Result<std::unique_ptr<Service>> first = Service::Create(config);
  ASSERT_TRUE(first.ok()) << first.message();
  ASSERT_GT((*first)->http_port(), 0);
  std::atomic<bool> stop{false};
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::seconds(2));
    // The health endpoint answers while the replay runs.
    httplib::Client client("127.0.0.1", (*first)->http_port());
    const httplib::Result health = client.Get("/health.json");
    ASSERT_TRUE(health);
    EXPECT_EQ(health->status, 200);
    EXPECT_NE(health->body.find("\"counters\""), std::string::npos);
    stop.store(true);
  });
  core::Result<nlohmann::ordered_json> stopped = (*first)->Run(stop);
  stopper.join();
  ASSERT_TRUE(stopped.ok()) << stopped.message();
  EXPECT_TRUE((*stopped)["stopped"].get<bool>());
  const core::Result<SavedState> state = ReadServiceState(dir / "out" / "state.json");
  ASSERT_TRUE(state.ok()) << state.message();
  const double stopped_at_s = state->stamp_s;
  EXPECT_GT(stopped_at_s, 1.0);
  EXPECT_LT(stopped_at_s, end_s - 1.0);
  first->reset();
  // As if the run had been killed after the save: lines past the saved state
  // and a last line cut in the middle. The restart cuts them off.
  std::ofstream(dir / "out" / "trajectory.tum", std::ios::app)
      << stopped_at_s + 5.0 << " 1 2 0 0 0 0 1\n"
      << stopped_at_s + 6.0 << " 1 2";
  std::ofstream(dir / "out" / "health.jsonl", std::ios::app)
      << "{\"stamp_s\": " << stopped_at_s + 5.0 << "}\n{\"stamp_s\": 1";

  // A restart resumes from the state and runs to the end of the drive.
  config.replay_speed = 0.0;
  core::Result<std::unique_ptr<Service>> second = Service::Create(config);
  ASSERT_TRUE(second.ok()) << second.message();
  std::atomic<bool> never{false};
  core::Result<nlohmann::ordered_json> finished = (*second)->Run(never);
  ASSERT_TRUE(finished.ok()) << finished.message();
  EXPECT_FALSE((*finished)["stopped"].get<bool>());
  EXPECT_EQ((*finished)["resumed"]["stale_lines_removed"].get<int>(), 4);
  std::ifstream health(dir / "out" / "health.jsonl");
  int health_lines = 0;
  double last_health_s = -1e300;
  for (std::string line; std::getline(health, line); ++health_lines) {
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    ASSERT_TRUE(j.is_object() && j.contains("stamp_s")) << "line " << health_lines << ": " << line;
    EXPECT_GT(j["stamp_s"].get<double>(), last_health_s) << "line " << health_lines;
    last_health_s = j["stamp_s"].get<double>();
  }
  EXPECT_GT(health_lines, 10);
  const core::Result<core::Trajectory> keyframes =
      core::ReadTumTrajectory(dir / "out" / "trajectory.tum");
  ASSERT_TRUE(keyframes.ok()) << keyframes.message();  // strictly increasing across the restart
  EXPECT_GT(keyframes->back().stamp_s, end_s - 1.0);
  // Close to the truth at the end (no jump at the restart).
  const core::SE2 truth =
      core::InterpolatePose(simulated->dataset.ground_truth, keyframes->back().stamp_s);
  EXPECT_LT((keyframes->back().pose.translation() - truth.translation()).norm(), 0.05);
}

TEST(Service, InjectedSensorFaultsAreCountedAndTheEstimateCoversWhatTheyCost) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP()
        << "minutes of Debug scan matching under AddressSanitizer; runs in the release build";
  }
  const auto dir = ::groundline::testing::ScratchDir("service_faults");
  const std::optional<sim::SimRun> simulated = testing::SimulatedZoneBDrive(30.0, 9, dir / "drive");
  ASSERT_TRUE(simulated.has_value());
  struct Case {
    InjectedFault fault;
    const char* counter;
  } cases[] = {
      {{InjectedFault::Sensor::kLidar, "silent", 8.0, 12.0}, "lidar_restarts"},
      {{InjectedFault::Sensor::kOdometry, "nan", 8.0, 9.0}, "wheel_dropped_non_finite"},
      {{InjectedFault::Sensor::kOdometry, "frozen", 8.0, 9.0}, "wheel_dropped_frozen"},
  };
  for (const Case& c : cases) {
    core::Result<nlohmann::ordered_json> summary =
        ReplayAsFastAsPossible(dir / "drive", dir / ("out_" + c.fault.kind), {c.fault});
    ASSERT_TRUE(summary.ok()) << summary.message();
    EXPECT_GE((*summary)["counters"][c.counter].get<long>(), 1) << c.fault.kind;
    // Without a camera nothing observes the motion along an aisle that the
    // lost readings carried, so the estimate cannot win it back; it must know
    // it: the final pose's error lies inside its covariance (chi-square, 2
    // dof, 99.9 %). A silent LiDAR loses nothing: back within 10 cm.
    const nlohmann::ordered_json& end = *summary;
    const core::SE2 truth =
        core::InterpolatePose(simulated->dataset.ground_truth, end["stamp_s"].get<double>());
    const Eigen::Vector2d error(end["pose"]["x_m"].get<double>() - truth.x(),
                                end["pose"]["y_m"].get<double>() - truth.y());
    Eigen::Matrix2d cov;
    cov << end["cov"][0].get<double>(), end["cov"][1].get<double>(), end["cov"][3].get<double>(),
        end["cov"][4].get<double>();
    // The covariance is in the base frame (right perturbation): rotate the error into it.
    const Eigen::Vector2d error_base = truth.Rotation().transpose() * error;
    EXPECT_LT(error_base.dot(cov.ldlt().solve(error_base)), 13.8)
        << c.fault.kind << ": error " << error.norm() << " m, sigma " << std::sqrt(cov.trace())
        << " m";
    if (c.fault.sensor == InjectedFault::Sensor::kLidar) {
      EXPECT_LT(error.norm(), 0.10);
    }
  }
}

TEST(Service, WheelReadingsThatStopForGoodLeaveTheFramesCountedAndTheRunEnds) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP()
        << "minutes of Debug scan matching under AddressSanitizer; runs in the release build";
  }
  const auto dir = ::groundline::testing::ScratchDir("service_no_odometry");
  std::optional<sim::SimRun> simulated = testing::SimulatedZoneBDrive(15.0, 5, dir / "drive", 2.0);
  ASSERT_TRUE(simulated.has_value());
  // The wheel encoders go silent after 4 s; the camera and the LiDAR go on.
  constexpr double kSilentAfterS = 4.0;
  core::Dataset& d = simulated->dataset;
  std::erase_if(d.wheel_encoders,
                [](const core::WheelEncoderReading& r) { return r.stamp_s > kSilentAfterS; });
  ASSERT_GT(d.images.size(), 20u);
  ASSERT_TRUE(core::WriteDataset(dir / "drive", d).ok());
  const double last_reading_s = d.wheel_encoders.back().stamp_s;
  const auto frames_after = [&](double t) {
    return std::count_if(d.images.begin(), d.images.end(),
                         [&](const core::ImageRecord& i) { return i.stamp_s > t; });
  };
  core::Result<nlohmann::ordered_json> summary = ReplayAsFastAsPossible(dir / "drive", dir / "out");
  ASSERT_TRUE(summary.ok()) << summary.message();
  // Every frame after the last reading (beyond the localizer's frame lag) is
  // counted as never met by odometry; the frames before it were used, and
  // the pose stops where the motion stopped.
  const long without = (*summary)["camera_stage"]["without_odometry"].get<long>();
  constexpr double kLagS = 1.0;  // more than the localizer's max_frame_lag_s
  EXPECT_GE(without, frames_after(last_reading_s + kLagS)) << summary->dump();
  EXPECT_LE(without, frames_after(last_reading_s - 1e-9));
  EXPECT_GE((*summary)["counters"]["frames_used"].get<long>(), 4);
  EXPECT_LE((*summary)["stamp_s"].get<double>(), last_reading_s + 1e-6);
}

// localizer.odometry_calibration: the wheel geometry and noise of the file
// drive the odometry in place of the manifest's nominal ones (a left wheel
// 1 % larger turns the dead-reckoned path to the right), and a file that
// cannot be read stops the start with its name.
TEST(Service, TheOdometryCalibrationReplacesTheNominalWheelGeometry) {
  const auto dir = ::groundline::testing::ScratchDir("service_odometry_calibration");
  std::optional<sim::SimRun> simulated = testing::SimulatedZoneBDrive(30.0, 5, dir / "drive");
  ASSERT_TRUE(simulated.has_value());
  const core::WheelEncoderSensor& nominal = *simulated->dataset.manifest.wheel_encoders;
  localization::OdometryCalibration calibration;
  calibration.drive.wheel_radius_m = nominal.wheel_radius_m;
  calibration.drive.left_wheel_radius_m = 1.01 * nominal.wheel_radius_m;
  calibration.drive.right_wheel_radius_m = nominal.wheel_radius_m;
  calibration.drive.track_m = nominal.track_m;
  calibration.wheel_variance_m2_per_m = 4e-5;
  calibration.lateral_variance_m2_per_m = 1e-7;
  ASSERT_TRUE(localization::WriteOdometryCalibration(dir / "odometry.json", calibration).ok());

  const auto run = [&](const std::string& odometry, const std::string& out) {
    ServiceConfig config;
    config.replay_dataset = (dir / "drive").string();
    config.replay_speed = 0.0;
    config.output_dir = (dir / out).string();
    config.http_enabled = false;
    config.resume = false;
    config.preset = "odometry";
    config.odometry_calibration = odometry;
    core::Result<std::unique_ptr<Service>> created = Service::Create(config);
    if (!created.ok()) return core::Result<core::Trajectory>(created.status());
    std::atomic<bool> never{false};
    core::Result<nlohmann::ordered_json> finished = (*created)->Run(never);
    if (!finished.ok()) return core::Result<core::Trajectory>(finished.status());
    return core::ReadTumTrajectory(dir / out / "trajectory_odometry_rate.tum");
  };
  const core::Result<core::Trajectory> plain = run("", "plain");
  ASSERT_TRUE(plain.ok()) << plain.message();
  const core::Result<core::Trajectory> calibrated = run((dir / "odometry.json").string(), "cal");
  ASSERT_TRUE(calibrated.ok()) << calibrated.message();
  ASSERT_EQ(plain->size(), calibrated->size());
  // The heading difference grows as the extra left travel over the track:
  // 1 % of the left wheel's travel (about the path length) / 0.76 m.
  double path_m = 0.0;
  for (std::size_t i = 1; i < plain->size(); ++i) {
    path_m += ((*plain)[i].pose.translation() - (*plain)[i - 1].pose.translation()).norm();
  }
  const double turned = std::remainder(calibrated->back().pose.yaw() - plain->back().pose.yaw(),
                                       2.0 * std::numbers::pi);
  EXPECT_NEAR(turned, -0.01 * path_m / nominal.track_m, 0.2 * 0.01 * path_m / nominal.track_m)
      << "path " << path_m << " m";

  const core::Result<core::Trajectory> missing = run((dir / "no_such.json").string(), "missing");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("no_such.json"), std::string::npos) << missing.message();
}

// localizer.self_calibration through the service's threads: the camera
// mount is estimated from the keyframes' lines and reported on every
// health.jsonl line; the drive's mount is the commissioned one, so no alarm.
// The run also keeps its atlas current (localizer.keep_atlas_current).
TEST(Service, SelfCalibrationReportsTheMountOnEveryKeyframe) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "a rendered drive and Debug scan matching under AddressSanitizer; runs in the "
                    "release build";
  }
  const auto dir = ::groundline::testing::ScratchDir("service_selfcal");
  ASSERT_TRUE(testing::SimulatedZoneBDrive(40.0, 12, dir / "drive", 2.0).has_value());
  ServiceConfig config;
  config.replay_dataset = (dir / "drive").string();
  config.replay_speed = 0.0;
  config.output_dir = (dir / "out").string();
  config.http_enabled = false;
  config.resume = false;
  config.self_calibration = true;
  config.preset = "lines";  // the estimator needs the lines, not the scan matching
  config.keep_atlas_current = true;
  core::Result<std::unique_ptr<Service>> created = Service::Create(config);
  ASSERT_TRUE(created.ok()) << created.message();
  std::atomic<bool> never{false};
  ASSERT_TRUE((*created)->Run(never).ok());
  {
    // The same run kept the atlas current (docs/atlas.md): atlas.json holds
    // the floor map's landmarks (this floor is as surveyed: nothing on it is
    // retired) and what was born.
    const nlohmann::json counters =
        nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"))["counters"];
    EXPECT_EQ(counters["landmarks_retired"].get<long>(), 0) << counters.dump();
    core::DatasetReadOptions read;
    read.check_image_files = false;
    const core::Result<core::Dataset> drive = core::ReadDataset(dir / "drive", read);
    ASSERT_TRUE(drive.ok() && drive->floor_map) << drive.message();
    const localization::Atlas surveyed = localization::AtlasFromFloorMap(
        *drive->floor_map, localization::AtlasFromFloorMapOptions());
    const core::Result<localization::Atlas> kept =
        localization::ReadAtlas(dir / "out" / "atlas.json");
    ASSERT_TRUE(kept.ok()) << kept.message();
    EXPECT_EQ(
        kept->lines.size() + kept->junctions.size(),
        surveyed.lines.size() + surveyed.junctions.size() + counters["landmarks_born"].get<long>());
  }
  std::ifstream health(dir / "out" / "health.jsonl");
  std::string text;
  int lines = 0, windows = 0;
  double last_pitch_deg = 0.0;
  while (std::getline(health, text)) {
    const nlohmann::json line = nlohmann::json::parse(text);
    ASSERT_TRUE(line.contains("selfcal_pitch_deg")) << text;
    EXPECT_FALSE(line["selfcal_alarm"].get<bool>()) << text;
    windows = line["selfcal_windows"].get<int>();
    last_pitch_deg = line["selfcal_pitch_deg"].get<double>();
    if (windows > 0) {
      EXPECT_NEAR(line["selfcal_pitch_deg"].get<double>(), 42.4, 0.5) << text;
      EXPECT_NEAR(line["selfcal_height_m"].get<double>(), 0.58, 0.02) << text;
    }
    ++lines;
  }
  EXPECT_GT(lines, 50);
  // The camera stage hands each frame's BEV on, and the floor's texture is
  // tracked at the keyframes: a window every 1.5 s of straight driving (7 in
  // this 32 s drive when written, pitch 0.0003 deg off), where the joints
  // crossing the view alone give one every few seconds.
  EXPECT_GE(windows, 5);
  EXPECT_NEAR(last_pitch_deg, 42.4, 0.05);

  // The estimate is kept for a restart: mount_estimate.json holds the last
  // one, and the next run (same output directory) starts from it.
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  const nlohmann::json& first = summary["self_calibration"];
  EXPECT_EQ(first["mount_estimate_restored"].get<std::string>(),
            "none saved: started from the commissioned mount");
  EXPECT_EQ(first["mount_estimate_write_failures"].get<long>(), 0);
  // The BEV follows no change here (within min_change of the commissioning,
  // or too uncertain); what it did is counted, and never failed.
  EXPECT_EQ(first["mount_rebuild_failures"].get<long>(), 0);
  const core::Result<calibration::SavedMountEstimate> saved =
      calibration::ReadMountEstimate(dir / "out" / "mount_estimate.json");
  ASSERT_TRUE(saved.ok()) << saved.message();
  EXPECT_EQ(saved->estimate.windows_used, windows);
  EXPECT_NEAR(saved->estimate.mount.pitch_rad * 180.0 / M_PI,
              first["selfcal_pitch_deg"].get<double>(), 1e-9);

  core::Result<std::unique_ptr<Service>> again = Service::Create(config);
  ASSERT_TRUE(again.ok()) << again.message();
  ASSERT_TRUE((*again)->Run(never).ok());
  const nlohmann::json second =
      nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"))["self_calibration"];
  EXPECT_NE(second["mount_estimate_restored"].get<std::string>().find("restored from"),
            std::string::npos)
      << second.dump();
  EXPECT_GT(second["selfcal_windows"].get<int>(), windows);

  // A saved estimate that cannot be read is reported and the run goes on
  // from the commissioned mount.
  std::ofstream(dir / "out" / "mount_estimate.json") << "{\"format\": 3";
  core::Result<std::unique_ptr<Service>> third = Service::Create(config);
  ASSERT_TRUE(third.ok()) << third.message();
  const nlohmann::json status = (*third)->StatusJson()["self_calibration"];
  EXPECT_NE(status["mount_estimate_restored"].get<std::string>().find("not restored"),
            std::string::npos)
      << status.dump();
  EXPECT_NE(status["mount_estimate_restored"].get<std::string>().find("mount_estimate.json"),
            std::string::npos)
      << status.dump();
  EXPECT_EQ(status["selfcal_windows"].get<int>(), 0);
}

TEST(Service, ReorderedDuplicatedReadingsAndABackwardClockJumpLoseNeitherMotionNorTheEstimate) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP()
        << "minutes of Debug scan matching under AddressSanitizer; runs in the release build";
  }
  const auto dir = ::groundline::testing::ScratchDir("service_time");
  // With the camera (2 Hz): the estimator holds readings for their frames,
  // and the camera stage runs ahead of it; neither may mistake the frames
  // after the clock's step for old ones.
  const std::optional<sim::SimRun> simulated =
      testing::SimulatedZoneBDrive(30.0, 9, dir / "drive", 2.0);
  ASSERT_TRUE(simulated.has_value());
  constexpr double kJumpS = -500.0;  // the clock steps back 500 s at 10 s
  const auto run = [&](const std::vector<InjectedFault>& faults, const std::string& name) {
    core::Result<nlohmann::ordered_json> summary =
        ReplayAsFastAsPossible(dir / "drive", dir / name, faults);
    EXPECT_TRUE(summary.ok()) << summary.message();
    return std::move(summary).value();
  };
  const auto error_m = [&](const nlohmann::ordered_json& end, double clock_s) {
    const core::SE2 truth = core::InterpolatePose(simulated->dataset.ground_truth,
                                                  end["stamp_s"].get<double>() - clock_s);
    return std::hypot(end["pose"]["x_m"].get<double>() - truth.x(),
                      end["pose"]["y_m"].get<double>() - truth.y());
  };
  const nlohmann::ordered_json clean = run({}, "clean");
  InjectedFault reorder{InjectedFault::Sensor::kOdometry, "reorder", 3.0, 7.0};
  InjectedFault duplicate{InjectedFault::Sensor::kOdometry, "duplicate", 12.0, 16.0};
  InjectedFault jump{InjectedFault::Sensor::kClock, "jump", 10.0, 0.0, kJumpS};
  const nlohmann::ordered_json faulty = run({reorder, duplicate, jump}, "faulty");
  const nlohmann::ordered_json& c = faulty["counters"];
  EXPECT_EQ(c["clock_jumps"].get<long>(), 1);
  EXPECT_GE(c["wheel_late_merged"].get<long>(), 150);        // ~200 swapped pairs in 4 s
  EXPECT_GE(c["wheel_dropped_duplicate"].get<long>(), 350);  // ~400 readings in 4 s
  EXPECT_EQ(c["wheel_dropped_out_of_order"].get<long>(), 0);
  EXPECT_LT(c["scans_dropped_out_of_order"].get<long>() + c["scans_dropped_ahead"].get<long>(), 5);
  // At most the frames of the few readings that reveal the step are lost.
  EXPECT_GE(c["frames_used"].get<long>(), clean["counters"]["frames_used"].get<long>() - 2)
      << "clean " << clean["counters"].dump() << "\nfaulty " << c.dump();
  // The outputs follow the source's new clock, and the pose is as good as
  // without the faults.
  EXPECT_NEAR(faulty["stamp_s"].get<double>(), clean["stamp_s"].get<double>() + kJumpS, 0.05);
  const double clean_m = error_m(clean, 0.0);
  const double faulty_m = error_m(faulty, kJumpS);
  EXPECT_LT(clean_m, 0.10);
  EXPECT_LT(faulty_m, clean_m + 0.03) << "clean " << clean_m << " m";
  // The heap is trimmed after every 10 s of data, whatever the replay's
  // speed: 30 s of data hold at most 3 trims, and a clock that steps back
  // restarts the count instead of stopping the trims (the 20 s after the
  // step hold at least one).
  for (const nlohmann::ordered_json* summary : {&clean, &faulty}) {
    const long trims = (*summary)["memory_trims"]["n"].get<long>();
    EXPECT_GE(trims, 1) << (*summary)["memory_trims"].dump();
    EXPECT_LE(trims, 3) << (*summary)["memory_trims"].dump();
  }
}

}  // namespace
}  // namespace groundline::service
