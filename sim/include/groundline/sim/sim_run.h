// One simulated run: a zone preset, a closed-loop route through it, and the
// sensor streams a differential-drive AGV records along it, assembled as a
// groundline dataset (docs/dataset.md) with ground truth and the floor map.
//
// The camera stream is not simulated yet (the floor renderer comes with the
// camera model); the dataset then has no camera and no images.
//
// Deterministic for given options: every random stream is seeded from `seed`.
// Not thread-safe across calls that share a progress callback.
#ifndef GROUNDLINE_SIM_SIM_RUN_H_
#define GROUNDLINE_SIM_SIM_RUN_H_

#include <cstdint>
#include <functional>
#include <string_view>

#include "groundline/core/dataset.h"
#include "groundline/core/status.h"
#include "groundline/localization/diff_drive_odometry.h"
#include "groundline/sim/lidar.h"
#include "groundline/sim/route.h"
#include "groundline/sim/wheel_encoders.h"
#include "groundline/sim/world.h"
#include "groundline/sim/zones.h"

namespace groundline::sim {

struct SimRunOptions {
  Zone zone = Zone::kB;
  // Seeds the zone preset, the route, the encoders and the LiDAR (each with
  // its own derived seed), overriding the seeds inside the option structs.
  std::uint64_t seed = 1;
  RouteOptions route;  // length_m, speeds, encoder/ground-truth rate (sample_rate_hz)
  localization::DiffDriveParams drive;
  // Encoder errors: 0.1 % radius error per wheel, random wheel travel error of
  // 1e-5 m^2/m, a slip of ~5 cm every 500 m on average. The route's clothoid
  // transitions deviate from an arc by ~2 um per 2 cm step; up to 10 um is
  // accepted (far below one encoder tick, 0.19 mm of wheel travel).
  WheelEncoderOptions encoders = [] {
    WheelEncoderOptions o;
    o.max_lateral_step_m = 1e-5;
    o.radius_scale_stddev = 1e-3;
    o.wheel_variance_m2_per_m = 1e-5;
    o.slip_rate_per_m = 2e-3;
    return o;
  }();
  bool with_lidar = true;
  LidarOptions lidar;

  core::Status Validate() const;
};

struct SimRun {
  World world;
  Route route;
  WheelEncoderLog encoder_log;  // with the slip events, for analysis
  core::Dataset dataset;        // manifest, encoders, scans, ground truth, floor map
};

// stage: "zone", "route", "encoders", "lidar"; fraction in [0, 1].
using SimProgress = std::function<void(std::string_view stage, double fraction)>;

// Errors: invalid options, a zone or route that cannot be built (the message
// names the option to change).
core::Result<SimRun> SimulateRun(const SimRunOptions& options, const SimProgress& progress = {});

// The world's markings as the dataset's floor map (ids in world order).
core::FloorMap ToFloorMap(const World& world);

// Converts a simulated scan to the dataset's encoding: no return and
// closer-than-minimum both become core::kNoReturnRange_m.
core::LaserScan ToDatasetScan(const LaserScan& scan);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_SIM_RUN_H_
