#include "groundline/sim/sim_run.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

#include "groundline/core/random_draws.h"
#include "groundline/core/text_parse.h"
#include "groundline/sim/floor_nuisances.h"
#include "groundline/sim/wall_faces.h"
#include "sim_run_internal.h"

namespace groundline::sim {

// Independent seeds for the random streams of one run (splitmix64 of the run
// seed and a stream number), so that changing one stream's options does not
// change the others.
std::uint64_t internal::StreamSeed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

namespace {

using internal::StreamSeed;

constexpr std::uint64_t kRouteStream = 1;
constexpr std::uint64_t kEncoderStream = 2;
constexpr std::uint64_t kLidarStream = 3;
constexpr std::uint64_t kCameraStream = 4;
constexpr std::uint64_t kClutterStream = 5;
constexpr std::uint64_t kSurveyStream = 6;

const char* ZoneLetter(Zone zone) {
  switch (zone) {
    case Zone::kA:
      return "A";
    case Zone::kB:
      return "B";
    case Zone::kC:
      return "C";
    case Zone::kD:
      return "D";
  }
  return "?";
}

}  // namespace

core::Result<World> internal::BuildRunZone(const SimRunOptions& options) {
  const auto seeded = [&options](auto layout) {
    layout.seed = options.seed;
    return layout;
  };
  switch (options.zone) {
    case Zone::kA:
      return BuildZoneA(seeded(options.zone_a));
    case Zone::kB:
      return BuildZoneB(seeded(options.zone_b));
    case Zone::kC:
      return BuildZoneC(seeded(options.zone_c));
    case Zone::kD:
      return BuildZoneD(seeded(options.zone_d));
  }
  return core::Status::Error("unknown zone");
}

namespace {

core::DatasetManifest MakeManifest(const SimRunOptions& options, const World& world) {
  core::DatasetManifest manifest;
  manifest.name =
      "sim_zone_" + std::string(ZoneLetter(options.zone)) + "_seed" + std::to_string(options.seed);
  manifest.description = "groundline simulator: " + world.name + ", " +
                         (options.route.closed_loop ? "closed loop of " : "route of ") +
                         std::to_string(static_cast<int>(std::lround(options.route.length_m))) +
                         " m";
  core::WheelEncoderSensor encoders;
  encoders.rate_hz = options.route.sample_rate_hz;
  encoders.wheel_radius_m = options.drive.wheel_radius_m;
  encoders.track_m = options.drive.track_m;
  encoders.ticks_per_rev = options.encoders.ticks_per_revolution;
  manifest.wheel_encoders = encoders;
  if (options.with_lidar) {
    core::LidarSensor lidar;
    lidar.rate_hz = options.lidar.rate_hz;
    lidar.T_base_lidar = options.lidar.T_base_lidar;
    lidar.mount_height_m = options.lidar.height_m;
    lidar.range_min_m = options.lidar.range_min_m;
    lidar.range_max_m = options.lidar.range_max_m;
    lidar.stamp = core::LidarStamp::kMidSweep;  // ToDatasetScan moves the stamp there
    manifest.lidar = lidar;
  }
  if (options.with_camera) {
    core::CameraSensor camera;
    camera.image_width_px = options.camera.width_px;
    camera.image_height_px = options.camera.height_px;
    camera.rate_hz = options.camera_rate_hz;
    manifest.camera = camera;
  }
  manifest.provenance["generator"] = "groundline sim";
  manifest.provenance["zone"] = ZoneLetter(options.zone);
  manifest.provenance["seed"] = std::to_string(options.seed);
  manifest.provenance["route_length_m"] = std::to_string(options.route.length_m);
  manifest.provenance["route_closed_loop"] = options.route.closed_loop ? "true" : "false";
  return manifest;
}

}  // namespace

core::Status SurveyNoiseOptions::Validate() const {
  const double sigmas[3] = {marking_vertex_sigma_m, face_offset_sigma_m, face_angle_sigma_rad};
  const char* names[3] = {"marking_vertex_sigma_m", "face_offset_sigma_m", "face_angle_sigma_rad"};
  for (int i = 0; i < 3; ++i) {
    if (!(std::isfinite(sigmas[i]) && sigmas[i] >= 0.0)) {
      return core::Status::Error(std::string(names[i]) + ": expected a sigma >= 0, got " +
                                 core::FormatShortestDouble(sigmas[i]));
    }
    // The map states the survey's accuracy; a stated sigma of 0 would claim
    // an exact survey of that part.
    if (enabled() && sigmas[i] == 0.0) {
      return core::Status::Error(std::string(names[i]) +
                                 ": expected a sigma > 0 when any survey noise is on");
    }
  }
  return core::Status::Ok();
}

SurveyNoiseOptions SurveyNoiseOptions::Typical() {
  SurveyNoiseOptions o;
  o.marking_vertex_sigma_m = 0.003;
  o.face_offset_sigma_m = 0.02;
  o.face_angle_sigma_rad = 0.2 * std::numbers::pi / 180.0;
  return o;
}

core::Status SimRunOptions::Validate() const {
  const core::Status layout = zone == Zone::kA   ? zone_a.Validate()
                              : zone == Zone::kB ? zone_b.Validate()
                              : zone == Zone::kC ? zone_c.Validate()
                                                 : zone_d.Validate();
  if (!layout.ok()) return layout.WithContext("layout");
  if (core::Status s = route.Validate(); !s.ok()) return s.WithContext("route");
  if (core::Status s = drive.Validate(); !s.ok()) return s.WithContext("drive");
  if (core::Status s = encoders.Validate(); !s.ok()) return s.WithContext("encoders");
  if (with_lidar) {
    if (core::Status s = lidar.Validate(); !s.ok()) return s.WithContext("lidar");
  }
  if (core::Status s = survey_noise.Validate(); !s.ok()) return s.WithContext("survey_noise");
  if (with_camera) {
    if (core::Status s = camera.Validate(); !s.ok()) return s.WithContext("camera");
    if (core::Status s = render.Validate(); !s.ok()) return s.WithContext("render");
    if (core::Status s = mount_perturbations.Validate(); !s.ok()) {
      return s.WithContext("mount_perturbations");
    }
    if (!(camera_rate_hz > 0.0 && camera_rate_hz <= camera.sensor_rate_hz)) {
      return core::Status::Error("camera_rate_hz: expected a rate in (0, camera.sensor_rate_hz = " +
                                 std::to_string(camera.sensor_rate_hz) + "], got " +
                                 std::to_string(camera_rate_hz));
    }
  }
  return core::Status::Ok();
}

core::FloorMap ToFloorMap(const World& world) {
  core::FloorMap map;
  map.markings.reserve(world.markings.size());
  for (std::size_t i = 0; i < world.markings.size(); ++i) {
    const FloorMarking& m = world.markings[i];
    core::FloorMarking out;
    out.id = static_cast<std::int64_t>(i);
    out.kind = m.kind;
    out.width_m = m.width_m;
    out.colour_rgb = MarkingColourRgb(m.colour);
    out.polarity = m.polarity;
    out.polyline_m = m.polyline_m;
    if (m.kind == MarkingKind::kTapeDashed) {
      out.dash_m = m.dash_length_m;
      out.gap_m = m.gap_length_m;
    }
    map.markings.push_back(std::move(out));
  }
  return map;
}

core::FloorMap SiteFloorMap(const World& world, double lidar_plane_height_m) {
  core::FloorMap map = ToFloorMap(world);
  WallFaceOptions options;
  options.plane_height_m = lidar_plane_height_m;
  auto next_id = static_cast<std::int64_t>(map.markings.size());
  for (const WallFace& face : WallFaces(world, options)) {
    core::FloorMarking out;
    out.id = next_id++;
    out.kind = face.rack_face ? MarkingKind::kRackFace : MarkingKind::kWall;
    out.width_m = 0.05;  // drawn thickness only: a face is its line
    out.colour_rgb = {96, 96, 96};
    out.polarity = core::MarkingPolarity::kDark;
    out.polyline_m = {face.a_m, face.b_m};
    map.markings.push_back(std::move(out));
  }
  return map;
}

core::FloorMap SurveyedFloorMap(const core::FloorMap& exact, const SurveyNoiseOptions& noise,
                                std::uint64_t seed) {
  if (!noise.enabled()) return exact;
  core::FloorMap map = exact;
  map.survey = core::FloorMapSurvey{noise.marking_vertex_sigma_m, noise.face_offset_sigma_m,
                                    noise.face_angle_sigma_rad};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (core::FloorMarking& marking : map.markings) {
    std::vector<core::Vector2>& v = marking.polyline_m;
    if (core::IsFaceKind(marking.kind)) {
      // A face as a whole: a turn about its midpoint, then a shift across it.
      const core::Vector2 mid = 0.5 * (v.front() + v.back());
      const core::Vector2 along = (v.back() - v.front()).normalized();
      const core::Vector2 normal(-along.y(), along.x());
      const double turn = noise.face_angle_sigma_rad * unit(rng);
      const double shift = noise.face_offset_sigma_m * unit(rng);
      const Eigen::Rotation2Dd R(turn);
      for (core::Vector2& p : v) p = mid + R * (p - mid) + shift * normal;
      continue;
    }
    const bool closed = v.size() > 2 && v.front() == v.back();
    for (core::Vector2& p : v) {
      p += noise.marking_vertex_sigma_m * core::DrawVector<2>(unit, rng);
    }
    if (closed) v.back() = v.front();
  }
  return map;
}

namespace {

// Half the sweep of a scan: the dataset stamps a scan at the middle of its
// sweep (docs/dataset.md), the simulator's LaserScan at its first ray.
double MidSweepS(const LidarOptions& options) {
  return 0.5 * static_cast<double>(options.NumRays() - 1) * options.TimeIncrementS();
}

}  // namespace

core::LaserScan ToDatasetScan(const LaserScan& scan) {
  core::LaserScan out;
  const double rays = static_cast<double>(scan.ranges_m.size());
  out.stamp_s = scan.stamp_s + 0.5 * std::max(0.0, rays - 1.0) * scan.time_increment_s;
  out.angle_min_rad = scan.angle_min_rad;
  out.angle_increment_rad = scan.angle_increment_rad;
  out.range_min_m = scan.range_min_m;
  out.range_max_m = scan.range_max_m;
  out.ranges_m.reserve(scan.ranges_m.size());
  for (const float r : scan.ranges_m) {
    out.ranges_m.push_back(std::isfinite(r) ? static_cast<double>(r) : core::kNoReturnRange_m);
  }
  out.intensities.assign(scan.intensities.begin(), scan.intensities.end());
  return out;
}

namespace internal {

core::Result<Route> PlanRobotRoute(const World& world, const SimRunOptions& options,
                                   std::uint64_t robot_seed) {
  RouteOptions route_options = options.route;
  route_options.seed = StreamSeed(robot_seed, kRouteStream);
  core::Result<Route> route = GenerateRoute(world, route_options);
  if (!route.ok()) return route.status().WithContext("generating the route");
  return route;
}

namespace {

// The floor camera's render options: the run's, or with
// randomize_nuisances a scene drawn per seed and zone.
FloorRenderOptions CameraRenderOptions(const SimRunOptions& options, std::uint64_t robot_seed) {
  FloorRenderOptions render = options.render;
  render.seed = StreamSeed(robot_seed, kCameraStream);
  if (!options.randomize_nuisances) return render;
  // Each zone of a seed is its own scene.
  FloorRenderOptions drawn = RandomizedRenderOptions(
      render.seed + 0x9E3779B9ULL * (static_cast<std::uint64_t>(options.zone) + 1));
  drawn.seed = render.seed;
  drawn.supersampling = render.supersampling;
  drawn.max_floor_range_m = render.max_floor_range_m;
  drawn.wall_dn = render.wall_dn;
  drawn.concrete_reflectance = render.concrete_reflectance;
  drawn.tape_reflectance_scale = render.tape_reflectance_scale;
  drawn.occlusion = render.occlusion;
  return drawn;
}

}  // namespace

core::Result<SimRun> SimulateRobot(World world, Route route, const SimRunOptions& options,
                                   std::uint64_t robot_seed, const SimProgress& progress) {
  const auto report = [&progress](std::string_view stage, double fraction) {
    if (progress) progress(stage, fraction);
  };
  SimRun run;
  run.world = std::move(world);
  run.route = std::move(route);
  const FloorRenderOptions render = CameraRenderOptions(options, robot_seed);
  if (options.with_camera && render.occlusion && render.standing_objects) {
    // Before the LiDAR, which sees the clutter too.
    AddRouteClutter(&run.world, run.route.T_map_base, render.clutter_per_100m, render,
                    StreamSeed(robot_seed, kClutterStream));
  }

  report("encoders", 0.0);
  WheelEncoderOptions encoder_options = options.encoders;
  encoder_options.seed = StreamSeed(robot_seed, kEncoderStream);
  core::Result<WheelEncoderLog> encoders =
      SimulateWheelEncoders(run.route.T_map_base, options.drive, encoder_options);
  if (!encoders.ok()) return encoders.status().WithContext("simulating the wheel encoders");
  run.encoder_log = std::move(encoders).value();
  report("encoders", 1.0);

  core::Dataset& dataset = run.dataset;
  dataset.manifest = MakeManifest(options, run.world);
  dataset.ground_truth = run.route.T_map_base;
  // One survey per site: every robot of a fleet gets the same map.
  dataset.floor_map = SurveyedFloorMap(
      SiteFloorMap(run.world,
                   options.with_lidar ? options.lidar.height_m : WallFaceOptions().plane_height_m),
      options.survey_noise, StreamSeed(options.seed, kSurveyStream));
  dataset.manifest.start_pose =
      core::StartPose{run.route.T_map_base.front().stamp_s, run.route.T_map_base.front().pose};
  dataset.wheel_encoders.reserve(run.encoder_log.readings.size());
  for (const EncoderReading& r : run.encoder_log.readings) {
    dataset.wheel_encoders.push_back({r.stamp_s, r.increment.left_rad, r.increment.right_rad});
  }

  if (options.with_lidar) {
    LidarOptions lidar_options = options.lidar;
    lidar_options.seed = StreamSeed(robot_seed, kLidarStream);
    const PlanarLidar lidar(run.world, lidar_options);
    const core::Trajectory& truth = run.route.T_map_base;
    const double t0 = truth.front().stamp_s;
    const double t1 = truth.back().stamp_s;
    const auto n_scans = static_cast<std::uint64_t>(std::floor((t1 - t0) * lidar_options.rate_hz));
    for (std::uint64_t k = 0; k <= n_scans; ++k) {
      const double t = t0 + static_cast<double>(k) / lidar_options.rate_hz;
      if (t + MidSweepS(lidar_options) > t1) break;
      dataset.scans.push_back(ToDatasetScan(lidar.ScanAlong(truth, t, k)));
      if (k % 200 == 0) report("lidar", static_cast<double>(k) / static_cast<double>(n_scans + 1));
    }
    report("lidar", 1.0);
  }
  if (options.with_camera) {
    core::Result<calibration::CameraModel> model = options.camera.MakeCameraModel();
    if (!model.ok()) return model.status().WithContext("building the floor camera");
    run.camera = SimCamera{std::move(model).value(), options.camera.mount, render};
    const core::Trajectory& truth = run.route.T_map_base;
    core::Result<std::vector<core::CameraExtrinsicsRecord>> mounts =
        MountSchedule(options.camera.mount, options.mount_perturbations, truth);
    if (!mounts.ok()) return mounts.status().WithContext("perturbing the camera mount");
    dataset.ground_truth_extrinsics = std::move(mounts).value();
    const double t0 = truth.front().stamp_s;
    const double t1 = truth.back().stamp_s;
    char name[32];
    for (std::uint64_t k = 0;; ++k) {
      const double t = t0 + static_cast<double>(k) / options.camera_rate_hz;
      if (t > t1) break;
      std::snprintf(name, sizeof(name), "%06llu.png", static_cast<unsigned long long>(k));
      dataset.images.push_back({t, name});
    }
  }
  dataset.UseDefaultFileNames();
  return run;
}

}  // namespace internal

core::Result<SimRun> SimulateRun(const SimRunOptions& options, const SimProgress& progress) {
  if (core::Status s = options.Validate(); !s.ok()) return s.WithContext("sim options");
  if (progress) progress("zone", 0.0);
  core::Result<World> world = internal::BuildRunZone(options);
  if (!world.ok()) return world.status().WithContext("building the zone");
  if (progress) progress("zone", 1.0);
  if (progress) progress("route", 0.0);
  core::Result<Route> route = internal::PlanRobotRoute(*world, options, options.seed);
  if (!route.ok()) return route.status();
  if (progress) progress("route", 1.0);
  return internal::SimulateRobot(std::move(world).value(), std::move(route).value(), options,
                                 options.seed, progress);
}

}  // namespace groundline::sim
