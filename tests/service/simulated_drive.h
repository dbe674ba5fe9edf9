// A short simulated zone B drive, written as a dataset: the input of the
// service tests (the LiDAR and the wheels; the camera at camera_rate_hz, 0:
// none, no rendering).
#ifndef GROUNDLINE_TESTS_SERVICE_SIMULATED_DRIVE_H_
#define GROUNDLINE_TESTS_SERVICE_SIMULATED_DRIVE_H_

#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <vector>

#include "groundline/core/dataset.h"
#include "groundline/core/status.h"
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

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_SERVICE_SIMULATED_DRIVE_H_
