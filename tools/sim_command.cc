// `groundline sim`: writes a simulated warehouse run as a groundline dataset.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/text_parse.h"
#include "groundline/sim/layout_png.h"
#include "groundline/sim/scenario.h"
#include "groundline/sim/sim_run.h"
#include "progress.h"

namespace groundline::tools {
namespace {

struct SimFlags {
  std::string scenario;
  std::string zone = "B";
  std::string length = "1200m";
  std::uint64_t seed = 1;
  std::string out_dir;
  bool closed_loop = false;
  bool no_lidar = false;
  bool no_camera = false;
  bool randomize_nuisances = false;
  bool survey_noise = false;
  double camera_rate_hz = 10.0;
  int threads = 2;
  // Which flags were given (they override the scenario file).
  std::vector<const CLI::Option*> given;
  bool Given(const char* name) const {
    for (const CLI::Option* o : given) {
      if (o->check_name(name) && o->count() > 0) return true;
    }
    return false;
  }
};

constexpr char kSimHelp[] =
    R"(Simulates a warehouse run with ground truth and writes it as a dataset
(docs/dataset.md) that 'groundline localize' replays.

Zones (presets modelled on a 24,000 m^2 logistics terminal):
  A  open staging hub: staging boxes, crosswalks, pallet stacks placed by the seed,
     forklifts and pedestrians crossing
  B  high-bay racks: 32 parallel aisles, 85 m long, 2.25 m clear, identical bays
     (the LiDAR-degenerate case), boundary tape, stop bars, expansion joints
  C  loading docks: 16 dock doors, apron and staging lanes
  D  inter-bay corridors: long smooth walls, saw-cut joints every 6.0 m, yellow
     boundary lines
The vehicle drives --length along the zone's lanes at 1-2 m/s, starting and
stopping at rest; the route is exactly that long. With --closed-loop it drives a
closed loop instead (back to its start at speed), as near --length as the lanes
allow (within 1 %, else an error; zone D's corridor ring comes in ~250 m laps).

Streams written: wheel encoders at 100 Hz (4096 ticks/rev, 0.1 % radius error per
wheel, random wheel error, occasional slips), planar LiDAR at 15 Hz (270 deg,
0.33 deg, 25 m, 1.5 cm noise, motion-distorted sweep), ground truth at 100 Hz, and
the floor-marking map, and the floor camera: 1280x1024 8-bit grey PNG frames
(OUT/images/NNNNNN.png, 6 mm lens, mild OpenCV distortion, 0.58 m high, pitched
42.4 deg down) rendered through the camera model with concrete texture, tape
wear, scuffs, oil, glare, illumination gradients, motion blur and sensor noise,
at --camera-rate (default 10 Hz; the sensor runs at 60 fps), with the intrinsics
(OUT/calibration/camera.yaml, OpenCV) and extrinsics (calibration/extrinsics.yaml).
Rendering costs a few frames per second per thread: --no-camera for quick runs.
Also writes OUT/layout.png: the zone with the route in red, and
OUT/nuisance_truth.json: the nuisances' parameters and the straight ones'
geometry (shadow edges, glare rows, tire marks, patch seams), simulator truth
that `groundline extract` uses to count false lines per nuisance class.

--randomize-nuisances draws every photometric nuisance per scene from wide
ranges (texture contrast, lux, gradient, shadows cast by racks, pallets and
the vehicle, glare size and count and strip rows, tire marks along the lanes,
patched concrete, wet areas, blur, noise), seeded by --seed: the randomized
evaluation set of docs/perception.md.

--survey-noise writes the floor map as a real survey would measure it instead
of the world's exact geometry: every marking vertex off by 3 mm (1 sigma per
axis, a tape survey), every wall and rack face off by 2 cm across and 0.2 deg
(a layout drawing); the map's survey block states these sigmas, and the
localizer weighs the map by them. A scenario sets other values under
survey_noise (marking_vertex_sigma_m, face_offset_sigma_m, face_angle_deg).
The ground truth stays exact; note that `extract --dataset` then scores the
detections against the surveyed map, survey errors included.

A scenario file (--scenario) sets everything else: the zone's layout, route
speeds, sensor rates and noise, each photometric nuisance on/off with its
intensity, and changes of the camera mount during the run (payload pitch,
tire-wear height loss, knocks; the true mount goes to
OUT/ground_truth_extrinsics.csv). Flags given on the command line override it.
See samples/scenarios/*.yaml and sim/include/groundline/sim/scenario.h.

With `robots: N` in the scenario, N vehicles drive the zone at once (own
routes, same floor map), each LiDAR seeing the others as moving boxes; robot k's
dataset goes to OUT/robot_<k>/ (see samples/scenarios/zone_a_fleet.yaml).
Robot k yields to robots 0..k-1 (same path, waiting where it must, 2.5 m apart)
and leaves the floor after its route; where waiting cannot keep two robots
apart (two routes down one corridor in opposite directions), the run fails
and says so: try another seed.

Examples:
  groundline sim --zone B --length 1200m --seed 7 --out zone_b_seed7
  groundline sim --scenario samples/scenarios/zone_b_payload_knock.yaml --out b_knock
  groundline sim --scenario samples/scenarios/zone_d_shadows.yaml --seed 3 --out d_seed3
  groundline sim --zone D --length 300m --no-lidar --camera-rate 2 --out quick_d
  groundline sim --zone B --length 200m --no-lidar --randomize-nuisances --seed 11 --out b_rand11
  groundline sim --zone A --length 600m --no-camera --out zone_a_no_camera)";

// "1200", "1200m", "1.2km" -> metres.
std::optional<double> ParseLengthM(const std::string& text) {
  std::string_view v = core::Trim(text);
  double scale = 1.0;
  if (v.ends_with("km")) {
    scale = 1000.0;
    v.remove_suffix(2);
  } else if (v.ends_with("m")) {
    v.remove_suffix(1);
  }
  const std::optional<double> value = core::ParseDouble(v);
  if (!value || !(*value > 0.0) || !std::isfinite(*value)) return std::nullopt;
  return *value * scale;
}

// The scenario file's options (or the defaults), then the flags given.
// Returns an exit code on error.
std::optional<int> AssembleOptions(const SimFlags& flags, sim::Scenario* scenario) {
  if (!flags.scenario.empty()) {
    core::Result<sim::Scenario> loaded = sim::LoadScenario(flags.scenario);
    if (!loaded.ok()) {
      std::fprintf(stderr, "groundline sim: --scenario: %s\n", loaded.message().c_str());
      return 1;
    }
    *scenario = std::move(loaded).value();
  }
  sim::SimRunOptions& options = scenario->options;
  const bool from_file = !flags.scenario.empty();
  if (!from_file || flags.Given("--zone")) {
    core::Result<sim::Zone> zone = sim::ParseZone(flags.zone);
    if (!zone.ok()) {
      std::fprintf(stderr, "groundline sim: --zone: %s\n", zone.message().c_str());
      return 2;
    }
    options.zone = *zone;
  }
  if (!from_file || flags.Given("--length")) {
    const std::optional<double> length_m = ParseLengthM(flags.length);
    if (!length_m) {
      std::fprintf(stderr,
                   "groundline sim: --length: expected a positive length such as 1200m or "
                   "1.2km, got '%s'\n",
                   flags.length.c_str());
      return 2;
    }
    options.route.length_m = *length_m;
  }
  if (!from_file || flags.Given("--seed")) options.seed = flags.seed;
  if (flags.closed_loop) options.route.closed_loop = true;
  if (flags.no_lidar) options.with_lidar = false;
  if (flags.no_camera) options.with_camera = false;
  if (flags.randomize_nuisances) options.randomize_nuisances = true;
  if (flags.survey_noise) options.survey_noise = sim::SurveyNoiseOptions::Typical();
  if (!from_file || flags.Given("--camera-rate")) options.camera_rate_hz = flags.camera_rate_hz;
  return std::nullopt;
}

// Writes one run into `out` (images and calibration first: WriteDataset
// checks that they exist) and prints its summary, naming the folder `shown`
// (where `out` is moved once everything is written). Returns the exit code.
int WriteRun(const std::filesystem::path& out, const std::filesystem::path& shown,
             const sim::SimRun& run, int threads, ProgressLine& progress, double started_s) {
  const auto update = [&progress](std::string_view stage, double fraction) {
    progress.Update(stage, fraction);
  };
  if (core::Status s = sim::WriteSimulatedImages(out, run, update, threads); !s.ok()) {
    std::fprintf(stderr, "groundline sim: %s\n", s.message().c_str());
    return 1;
  }
  progress.Update("writing", 0.0);
  if (core::Status s = sim::WriteNuisanceTruth(out, run); !s.ok()) {
    std::fprintf(stderr, "groundline sim: %s\n", s.message().c_str());
    return 1;
  }
  if (core::Status s = sim::WriteVehicleTruth(out, run); !s.ok()) {
    std::fprintf(stderr, "groundline sim: %s\n", s.message().c_str());
    return 1;
  }
  if (core::Status s = core::WriteDataset(out, run.dataset); !s.ok()) {
    std::fprintf(stderr, "groundline sim: %s\n", s.message().c_str());
    return 1;
  }
  if (core::Status s = sim::WriteLayoutPng(run.world, &run.route.T_map_base, out / "layout.png");
      !s.ok()) {
    std::fprintf(stderr, "groundline sim: layout picture: %s\n", s.message().c_str());
    return 1;
  }
  progress.Update("writing", 1.0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count() -
      started_s;
  const std::map<std::string, std::string>& provenance = run.dataset.manifest.provenance;
  std::printf(
      "%s: zone %s, seed %s, %.0f m in %.0f s of driving; %zu encoder readings, "
      "%zu LiDAR scans, %zu camera frames, %zu floor markings, %zu wheel slips; simulated in "
      "%.1f s\n",
      shown.string().c_str(), provenance.at("zone").c_str(), provenance.at("seed").c_str(),
      run.route.length_m, run.route.duration_s, run.dataset.wheel_encoders.size(),
      run.dataset.scans.size(), run.dataset.images.size(),
      run.dataset.floor_map ? run.dataset.floor_map->markings.size() : 0,
      run.encoder_log.slips.size(), seconds);
  // A few sample frames (the dataset's own images, spread over the run).
  const std::vector<core::ImageRecord>& images = run.dataset.images;
  for (std::size_t i = 0; i < std::min<std::size_t>(4, images.size()); ++i) {
    const std::size_t k = i * (images.size() - 1) / std::max<std::size_t>(1, 3);
    std::printf("sample frame: %s (t = %.2f s)\n",
                (shown / "images" / images[k].file).string().c_str(), images[k].stamp_s);
  }
  return 0;
}

int RunSim(const SimFlags& flags) {
  const double started_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  sim::Scenario scenario;
  if (const std::optional<int> code = AssembleOptions(flags, &scenario)) return *code;
  const sim::SimRunOptions& options = scenario.options;
  ProgressLine progress("[sim]");
  const auto update = [&progress](std::string_view stage, double fraction) {
    progress.Update(stage, fraction);
  };
  // Written into a staging folder moved into --out at the end: a run that
  // fails (or is interrupted) leaves --out as it was.
  const std::filesystem::path shown(flags.out_dir);
  const auto commit = [&](core::StagedDirectory& staged) {
    if (core::Status s = staged.Commit(); !s.ok()) {
      std::fprintf(stderr, "groundline sim: %s\n", s.message().c_str());
      return 1;
    }
    return 0;
  };
  if (scenario.robots == 1) {
    core::Result<sim::SimRun> run = sim::SimulateRun(options, update);
    if (!run.ok()) {
      std::fprintf(stderr, "groundline sim: %s\n", run.message().c_str());
      return 1;
    }
    core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(flags.out_dir);
    if (!staged.ok()) {
      std::fprintf(stderr, "groundline sim: %s\n", staged.message().c_str());
      return 1;
    }
    if (const int code =
            WriteRun(staged->path(), shown, *run, flags.threads, progress, started_s)) {
      return code;
    }
    return commit(*staged);
  }
  sim::FleetOptions fleet;
  fleet.robots = scenario.robots;
  core::Result<std::vector<sim::SimRun>> runs = sim::SimulateFleet(options, fleet, update);
  if (!runs.ok()) {
    std::fprintf(stderr, "groundline sim: %s\n", runs.message().c_str());
    return 1;
  }
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(flags.out_dir);
  if (!staged.ok()) {
    std::fprintf(stderr, "groundline sim: %s\n", staged.message().c_str());
    return 1;
  }
  for (std::size_t k = 0; k < runs->size(); ++k) {
    const std::string robot = "robot_" + std::to_string(k);
    if (const int code = WriteRun(staged->path() / robot, shown / robot, (*runs)[k], flags.threads,
                                  progress, started_s)) {
      return code;
    }
  }
  return commit(*staged);
}

}  // namespace

CLI::App* AddSimCommand(CLI::App& parent, CommandRunner* run) {
  auto flags = std::make_shared<SimFlags>();
  CLI::App* cmd = parent.add_subcommand("sim", "Simulate a warehouse run (zones A-D) as a dataset");
  cmd->footer(kSimHelp);
  cmd->add_option("--scenario", flags->scenario,
                  "Scenario YAML (samples/scenarios/*.yaml): layout, route, sensors, nuisances, "
                  "mount perturbations; the flags given override it")
      ->check(CLI::ExistingFile);
  flags->given.push_back(
      cmd->add_option("--zone", flags->zone, "Zone preset: A, B, C or D")->capture_default_str());
  flags->given.push_back(
      cmd->add_option("--length", flags->length, "Route length (e.g. 1200m, 1.2km)")
          ->capture_default_str());
  flags->given.push_back(
      cmd->add_option("--seed", flags->seed, "Seed of every random choice")->capture_default_str());
  cmd->add_option("-o,--out", flags->out_dir, "Output dataset directory")->required();
  cmd->add_flag("--closed-loop", flags->closed_loop,
                "Drive a closed loop back to the start (length as near --length as the lanes "
                "allow, within 1 %)");
  cmd->add_flag("--no-lidar", flags->no_lidar, "Skip the LiDAR stream (faster, smaller)");
  cmd->add_flag("--no-camera", flags->no_camera,
                "Skip the floor camera (no images; much faster, much smaller)");
  cmd->add_flag("--randomize-nuisances", flags->randomize_nuisances,
                "Draw every photometric nuisance per scene from wide ranges (seeded by --seed)");
  cmd->add_flag("--survey-noise", flags->survey_noise,
                "Write the floor map as a survey measured it: 3 mm per marking vertex, faces "
                "from a layout drawing off by 2 cm and 0.2 deg (the map states these sigmas)");
  flags->given.push_back(
      cmd->add_option("--camera-rate", flags->camera_rate_hz,
                      "Camera frames per second written, Hz (0 < rate <= 60, the sensor's rate)")
          ->capture_default_str());
  cmd->add_option("--threads", flags->threads, "Threads rendering camera frames")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->callback([flags, run] { *run = [flags] { return RunSim(*flags); }; });
  return cmd;
}

}  // namespace groundline::tools
