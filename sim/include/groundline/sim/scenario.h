// Scenario files for `groundline sim --scenario FILE.yaml`: everything the
// command's flags do not cover, as YAML (examples: samples/scenarios/*.yaml).
//
//   format: groundline-sim-scenario
//   version: 1.0
//   zone: B                  # A, B, C or D
//   seed: 7
//   robots: 1                # vehicles in the zone at once (one dataset each)
//   layout: {num_aisles: 12, pallet_fill: 0.8}   # the zone's options (zones.h)
//   route: {length_m: 1200, closed_loop: false, min_speed_mps: 1, max_speed_mps: 2, ...}
//   encoders: {ticks_per_revolution: 4096, slip_rate_per_m: 0.002, ...}
//             # the true vehicle against the manifest's nominal geometry:
//             # left_radius_scale, right_radius_scale, track_scale (1: as
//             # nominal), radius_scale_stddev (a random draw per seed)
//   lidar: {enabled: true, rate_hz: 15, range_noise_sigma_m: 0.015, ...}
//   camera: {enabled: true, rate_hz: 10, width_px: 1280, mount: {pitch_deg: 42.4, ...}}
//   nuisances:               # each with enabled and its intensity
//     randomized: {enabled: true}  # every nuisance drawn per scene (floor_nuisances.h);
//                                  # it replaces the other sections' values
//     texture: {enabled: true, contrast: 0.25}
//     scuffs: {enabled: true, darkness: 0.15}
//     shadows: {enabled: true, factor: 0.4, cover: 0.3}
//     occlusion: {enabled: true}   # forklifts, pedestrians, robots in view
//     standing_objects: {enabled: true, clutter_per_100m: 5}  # racks, pallets, boxes, posts
//     ...
//   perturbations:           # the camera mount during the run (mount_perturbation.h)
//     height_loss_mm_per_km: 2
//     steps:
//       - {cause: payload, at_s: 60, pitch_deg: 0.5}
//       - {cause: knock, at_s: 120, yaw_deg: 1.0, roll_deg: -0.3}
//
// Every key is optional except format and version; absent keys keep the
// defaults of SimRunOptions. Keys carry their units (_m, _deg, _mm, _s, _hz);
// angles are degrees and perturbation lengths millimetres in the file, radians
// and metres in the options. Unknown keys are errors (typos are caught). Every
// error names the file, the line and the field, e.g.
//   "s.yaml:9: field 'route.max_speed_mps': expected a finite number, got 'fast'";
// options that parse but are out of range are reported with the file and the
// Options field ("s.yaml: route: RouteOptions.max_speed_mps: expected ...").
#ifndef GROUNDLINE_SIM_SCENARIO_H_
#define GROUNDLINE_SIM_SCENARIO_H_

#include <filesystem>
#include <string>

#include "groundline/core/status.h"
#include "groundline/sim/sim_run.h"

namespace groundline::sim {

inline constexpr char kScenarioFormatName[] = "groundline-sim-scenario";
inline constexpr int kScenarioFormatMajor = 1;
inline constexpr int kScenarioFormatMinor = 0;

struct Scenario {
  SimRunOptions options;
  int robots = 1;  // >= 1
};

// Reads and validates a scenario file (SimRunOptions::Validate included).
core::Result<Scenario> LoadScenario(const std::filesystem::path& path);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_SCENARIO_H_
