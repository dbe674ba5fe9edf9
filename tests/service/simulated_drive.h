// A short simulated zone B drive, written as a dataset: the input of the
// service tests (the LiDAR and the wheels; the camera at camera_rate_hz, 0:
// none, no rendering).
#ifndef GROUNDLINE_TESTS_SERVICE_SIMULATED_DRIVE_H_
#define GROUNDLINE_TESTS_SERVICE_SIMULATED_DRIVE_H_

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "groundline/core/dataset.h"
#include "groundline/core/status.h"
#include "groundline/service/service.h"
#include "groundline/service/service_config.h"
#include "groundline/sim/sim_run.h"

namespace groundline::testing {

// The simulated run (its dataset holds the ground truth), also written to
// dir; nullopt after a test failure naming what went wrong.
inline std::optional<sim::SimRun> SimulatedZoneBDrive(double length_m, std::uint64_t seed,
                                                      const std::filesystem::path& dir,
                                                      double camera_rate_hz = 0.0) {
  sim::SimRunOptions options;
  options.zone = sim::Zone::kB;
  options.route.length_m = length_m;
  options.seed = seed;
  options.with_camera = camera_rate_hz > 0.0;
  if (options.with_camera) options.camera_rate_hz = camera_rate_hz;
  core::Result<sim::SimRun> run = sim::SimulateRun(options);
  if (!run.ok()) {
    ADD_FAILURE() << run.message();
    return std::nullopt;
  }
  if (options.with_camera) {
    if (core::Status s = sim::WriteSimulatedImages(dir, *run); !s.ok()) {
      ADD_FAILURE() << s.message();
      return std::nullopt;
    }
  }
  if (core::Status s = core::WriteDataset(dir, run->dataset); !s.ok()) {
    ADD_FAILURE() << s.message();
    return std::nullopt;
  }
  return std::move(run).value();
}

// The service replaying dataset_dir as fast as possible into out_dir, fresh
// (no resume), without its HTTP endpoint, with the given injected faults.
inline core::Result<nlohmann::ordered_json> ReplayAsFastAsPossible(
    const std::filesystem::path& dataset_dir, const std::filesystem::path& out_dir,
    std::vector<service::InjectedFault> faults = {}) {
  service::ServiceConfig config;
  config.replay_dataset = dataset_dir.string();
  config.replay_speed = 0.0;
  config.output_dir = out_dir.string();
  config.http_enabled = false;
  config.resume = false;
  config.faults = std::move(faults);
  core::Result<std::unique_ptr<service::Service>> created = service::Service::Create(config);
  if (!created.ok()) return created.status();
  std::atomic<bool> never{false};
  return (*created)->Run(never);
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_SERVICE_SIMULATED_DRIVE_H_
