// `groundline serve --config FILE`: flags and config to service::Service.

#include <atomic>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "groundline/service/service.h"
#include "groundline/service/service_config.h"

namespace groundline::tools {
namespace {

std::atomic<bool> g_stop{false};

extern "C" void OnStopSignal(int) { g_stop.store(true); }

constexpr char kServeHelp[] =
    R"(Runs the localizer as a service: one process, one YAML config (every key
and its default: docs/service.md). Inputs: a dataset replayed at its own
timestamps (inputs.replay.speed: 1 real time, N times faster, 0 as fast as
possible), or ROS 2 topics over DDS (inputs.dds: /odom or /joint_states,
/scan, /camera/image_raw, /initialpose; the dataset then only gives the
calibration, the floor map and the start pose). Outputs on ROS 2 topics with
output.dds: /groundline/pose, /tf (map -> odom), /diagnostics. Domain:
ROS_DOMAIN_ID; network: CYCLONEDDS_URI (unset: loopback only). Stages on their own threads with bounded queues: a slow camera
stage drops frames and counts them, and never blocks the odometry.

Outputs in output.dir: trajectory.tum (keyframes), trajectory_odometry_rate.tum,
health.jsonl (one line per keyframe), summary.json, state.json. On SIGINT or
SIGTERM it finishes the outputs, saves its state and exits 0; with start.resume
(the default) a restart continues from state.json.

Status: http://127.0.0.1:8088/ (http.address, http.port) shows the bird's-eye
view with the detected lines, the pose on the atlas with its covariance
ellipse, input rates, dropped counts and the LiDAR degeneracy;
/health.json is the same as JSON.

Example config (samples/config/serve_replay.yaml):
  inputs:
    replay: {dataset: ../data/zone_b, speed: 4}
  localizer: {preset: fusion}
  output: {dir: run_service}
  http: {port: 8088}

Examples:
  groundline serve --config samples/config/serve_replay.yaml
  ROS_DOMAIN_ID=7 groundline serve --config samples/config/serve_dds.yaml
  groundline serve --config site.yaml --speed 0      # replay as fast as possible)";

}  // namespace

CLI::App* AddServeCommand(CLI::App& parent, CommandRunner* run) {
  auto config_path = std::make_shared<std::string>();
  auto speed = std::make_shared<double>(-1.0);
  auto port = std::make_shared<int>(-1);
  CLI::App* cmd = parent.add_subcommand("serve", "Run the localizer as a service (config file)");
  cmd->footer(kServeHelp);
  cmd->add_option("-c,--config", *config_path, "Service configuration (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--speed", *speed, "Override inputs.replay.speed (0: as fast as possible)")
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--port", *port, "Override http.port (0: any free port)")
      ->check(CLI::Range(0, 65535));
  cmd->callback([config_path, speed, port, run] {
    *run = [config_path, speed, port] {
      core::Result<service::ServiceConfig> config = service::ReadServiceConfig(*config_path);
      if (!config.ok()) {
        std::fprintf(stderr, "groundline serve: %s\n", config.message().c_str());
        return 1;
      }
      if (*speed >= 0.0) config->replay_speed = *speed;
      if (*port >= 0) config->http_port = *port;
      core::Result<std::unique_ptr<service::Service>> created = service::Service::Create(*config);
      if (!created.ok()) {
        std::fprintf(stderr, "groundline serve: %s\n", created.message().c_str());
        return 1;
      }
      std::signal(SIGINT, OnStopSignal);
      std::signal(SIGTERM, OnStopSignal);
      if ((*created)->http_port() > 0) {
        std::printf("groundline serve: status page http://%s:%d/ (health: /health.json)\n",
                    config->http_address.c_str(), (*created)->http_port());
        std::fflush(stdout);
      }
      core::Result<nlohmann::ordered_json> summary = (*created)->Run(g_stop);
      if (!summary.ok()) {
        std::fprintf(stderr, "groundline serve: %s\n", summary.message().c_str());
        return 1;
      }
      std::printf("groundline serve: %s; outputs in %s\n",
                  g_stop.load() ? "stopped by a signal, state saved" : "inputs ended",
                  config->output_dir.c_str());
      return 0;
    };
  });
  return cmd;
}

}  // namespace groundline::tools
