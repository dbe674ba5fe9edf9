// One simulated run: a zone preset, a closed-loop route through it, and the
// sensor streams a differential-drive AGV records along it, assembled as a
// groundline dataset (docs/dataset.md) with ground truth and the floor map.
//
// The camera stream (with_camera) is planned here and rendered by
// WriteSimulatedImages: SimulateRun fills the manifest's camera and the image
// index (stamps and file names) but renders nothing, because core::WriteDataset
// only checks that images and calibration files exist. Writing a run with a
// camera is therefore two calls:
//   WriteSimulatedImages(dir, run, progress);   // images/*.png, calibration/*
//   core::WriteDataset(dir, run.dataset);       // index, streams, manifest last
//
// Deterministic for given options: every random stream is seeded from `seed`.
// Not thread-safe across calls that share a progress callback.
#ifndef GROUNDLINE_SIM_SIM_RUN_H_
#define GROUNDLINE_SIM_SIM_RUN_H_

#include <cstdint>
#include <functional>
#include <string_view>

#include <filesystem>
#include <optional>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/dataset.h"
#include "groundline/core/status.h"
#include "groundline/localization/diff_drive_odometry.h"
#include "groundline/sim/floor_camera.h"
#include "groundline/sim/lidar.h"
#include "groundline/sim/mount_perturbation.h"
#include "groundline/sim/fleet_traffic.h"
#include "groundline/sim/route.h"
#include "groundline/sim/wheel_encoders.h"
#include "groundline/sim/world.h"
#include "groundline/sim/zones.h"

namespace groundline::sim {

// The errors of the survey a site's floor map comes from. All zero (the
// default): the dataset's floor map is the world's exact geometry. All > 0:
// every vertex of a floor marking moves by N(0, marking_vertex_sigma_m^2)
// along each axis, every wall and rack face shifts across itself by
// N(0, face_offset_sigma_m^2) and turns about its midpoint by
// N(0, face_angle_sigma_rad^2); the map states these sigmas in its survey
// block, as an honest survey would.
struct SurveyNoiseOptions {
  double marking_vertex_sigma_m = 0.0;
  double face_offset_sigma_m = 0.0;
  double face_angle_sigma_rad = 0.0;
  bool enabled() const {
    return marking_vertex_sigma_m > 0.0 || face_offset_sigma_m > 0.0 || face_angle_sigma_rad > 0.0;
  }
  core::Status Validate() const;
  // A tape survey of the markings (3 mm per vertex) and faces taken from a
  // layout drawing (2 cm, 0.2 deg).
  static SurveyNoiseOptions Typical();
};

struct SimRunOptions {
  Zone zone = Zone::kB;
  // The layout of each zone (only the one of `zone` is used; its seed is
  // replaced by `seed`).
  ZoneAOptions zone_a;
  ZoneBOptions zone_b;
  ZoneCOptions zone_c;
  ZoneDOptions zone_d;
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
  // The floor camera: images at camera_rate_hz (the 60 fps sensor subsampled;
  // the manifest states camera_rate_hz), rendered per floor_camera.h. The
  // renderer's seed is derived from `seed`.
  bool with_camera = true;
  double camera_rate_hz = 10.0;
  FloorCameraOptions camera;
  FloorRenderOptions render;
  // Every photometric nuisance drawn per scene from wide ranges
  // (RandomizedRenderOptions, floor_nuisances.h, seeded by the camera's
  // stream seed and the zone): render's nuisance fields are replaced; its supersampling,
  // floor range, wall tone, reflectances and occlusion switch are kept.
  bool randomize_nuisances = false;
  // Changes of the camera mount during the run (payload, tire wear, knocks):
  // frames are rendered through the true mount of their moment, the dataset's
  // extrinsics file keeps camera.mount (nominal) and its
  // ground_truth_extrinsics the true mount over time.
  MountPerturbationOptions mount_perturbations;
  // The floor map's survey errors (one draw per site, seeded by `seed`).
  SurveyNoiseOptions survey_noise;

  core::Status Validate() const;
};

// What WriteSimulatedImages needs to render the run's frames.
struct SimCamera {
  calibration::CameraModel model;
  calibration::CameraMount mount;  // nominal (the calibration file); the true
                                   // mount over time: dataset.ground_truth_extrinsics
  FloorRenderOptions render;       // seed already derived from the run's seed
};

struct SimRun {
  World world;
  Route route;
  WheelEncoderLog encoder_log;      // with the slip events, for analysis
  core::Dataset dataset;            // manifest, encoders, scans, ground truth, floor map
  std::optional<SimCamera> camera;  // set iff dataset.manifest.camera is
};

// stage: "zone", "route", "encoders", "lidar" (SimulateRun), "camera"
// (WriteSimulatedImages); fraction in [0, 1].
using SimProgress = std::function<void(std::string_view stage, double fraction)>;

// Errors: invalid options, a zone or route that cannot be built (the message
// names the option to change).
core::Result<SimRun> SimulateRun(const SimRunOptions& options, const SimProgress& progress = {});

// Several robots in one zone at once (fleet runs). One world (built from
// options.seed); robot k drives its own route (a different start and walk)
// with its own encoder, LiDAR and camera noise, all seeded from its robot seed
// (robot 0: options.seed, so a one-robot fleet is SimulateRun; robot k > 0:
// derived from options.seed and k). Every robot's LiDAR sees every other robot
// as a moving box (FleetOptions) that follows that robot's ground truth and is
// parked at its first or last pose before or after its run. Each SimRun's
// world holds the other robots as MovingKind::kRobot obstacles; the floor map
// is the same for all. Robots do not avoid each other (no traffic rules):
// their routes may cross, and a LiDAR inside another robot's box reports
// too-close (no) returns there. Manifest names end in "_robot<k>".
struct FleetOptions {
  int robots = 2;  // >= 1
  // The vehicle body seen by the others' LiDARs: a box centred on base_link.
  Vector2 robot_half_extent_m = Vector2(0.85, 0.46);
  double robot_height_m = 1.2;
  double robot_reflectivity = 0.6;
  // How the robots keep apart (fleet_traffic.h): robot k yields to robots
  // 0..k-1. Its acceleration limit is the route's.
  TrafficOptions traffic;

  core::Status Validate() const;
};
core::Result<std::vector<SimRun>> SimulateFleet(const SimRunOptions& options,
                                                const FleetOptions& fleet,
                                                const SimProgress& progress = {});

// Renders every frame of run.dataset.images at its stamp (pose interpolated
// from the ground truth, motion blur from its velocity, noise seeded by the
// frame index, through the true mount in force at the stamp per
// run.dataset.ground_truth_extrinsics, or the nominal mount when that is
// empty) and writes DIR/images/<file> (PNG, atomically), then the
// calibration files named by the manifest's camera: the intrinsics as an OpenCV
// YAML (calibration::WriteOpenCvCalibration) and the mount as a groundline
// extrinsics file (calibration::WriteCameraMountYaml). Frames are split over
// `threads` worker threads (>= 1; the images do not depend on it). A run
// without a camera writes nothing. Errors name the file that failed.
core::Status WriteSimulatedImages(const std::filesystem::path& dir, const SimRun& run,
                                  const SimProgress& progress = {}, int threads = 1);

// Writes DIR/nuisance_truth.json (atomically): the simulator's truth about
// the floor's nuisances, for evaluation only (floor_nuisances.h). It holds the
// render options' nuisance parameters, the straight nuisances fixed on the
// floor within the world (map frame) and, per camera frame, the vehicle's
// shadow polygon (base_link). Format in docs/perception.md. A run without a
// camera writes nothing.
core::Status WriteNuisanceTruth(const std::filesystem::path& dir, const SimRun& run);

// Writes DIR/vehicle_truth.json (atomically): the vehicle's true odometry
// geometry and noise (each wheel's effective radius, the effective track, the
// wheel travel variance, the slips) beside the nominal geometry the manifest
// states, for evaluation only (odometry calibration). A run without wheel
// encoders writes nothing.
core::Status WriteVehicleTruth(const std::filesystem::path& dir, const SimRun& run);

// The world's markings as the dataset's floor map (ids in world order).
core::FloorMap ToFloorMap(const World& world);

// What a site has: the floor survey (ToFloorMap) followed by the wall and rack
// faces of its installation drawing (wall_faces.h, in the LiDAR plane at
// lidar_plane_height_m) as markings of kind wall / rack_face, ids after the
// markings'. The dataset's floor_map.yaml.
core::FloorMap SiteFloorMap(const World& world, double lidar_plane_height_m);

// The site's floor map as a survey with `noise` measured it (see
// SurveyNoiseOptions), with its survey block; `exact` itself when the noise
// is off. A closed outline stays closed.
core::FloorMap SurveyedFloorMap(const core::FloorMap& exact, const SurveyNoiseOptions& noise,
                                std::uint64_t seed);

// Converts a simulated scan to the dataset's encoding: no return and
// closer-than-minimum both become core::kNoReturnRange_m, and the stamp moves
// from the first ray to the middle of the sweep (docs/dataset.md).
core::LaserScan ToDatasetScan(const LaserScan& scan);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_SIM_RUN_H_
