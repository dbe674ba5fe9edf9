// `groundline localize`: a thin driver of the causal localizer
// (localization/localizer.h): a dataset's streams replayed in time order
// (service/replay.h), or a CARMEN log through the LiDAR SLAM; writes the run
// outputs (trajectory.tum, health.jsonl, summary.json; docs/localization.md).
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "groundline/core/angles.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/dataset_streams.h"
#include "groundline/core/run_timing.h"
#include "groundline/core/text_parse.h"
#include "groundline/core/trajectory_covariance_io.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/atlas_walls.h"
#include "groundline/localization/keyframe_mount_calibration.h"
#include "groundline/localization/localizer_json.h"
#include "groundline/localization/odometry_calibration.h"
#include "groundline/service/dataset_localizer.h"
#include "groundline/service/replay.h"
#include "localize_carmen.h"
#include "localize_checks.h"
#include "localize_diagnostics.h"
#include "progress.h"
#include "run_summary.h"

namespace groundline::tools {
namespace {

namespace fs = std::filesystem;
namespace loc = localization;
using core::Percentile;

struct LocalizeFlags {
  std::string dataset_dir;
  std::string out_dir;
  std::string mode = "odometry";
  std::vector<double> initial_pose;  // x_m y_m yaw_deg
  std::string atlas_path;
  std::string atlas_out_path;
  std::string odometry_path;
  std::string odometry_out_path;
  std::string surveyed_path;
  bool diagnose = false;
  bool lidar = false;
  bool wall_lines = true;
  bool relocalize = false;
  bool self_calibrate = false;
  bool self_calibrate_report_only = false;
  std::vector<double> near;  // x_m y_m [radius_m]
  std::string solver = "chain";
  double max_duration_s = 0.0;
  // Optional overrides of the preset (negative: keep the preset's value).
  double window_s = -1.0;
  double gate_chi2 = -1.0;
  double slip_sigma_m = -1.0;
  double wheel_variance_m2_per_m = -1.0;
  double lateral_variance_m2_per_m = -1.0;
};

constexpr char kLocalizeHelp[] =
    R"(Replays a groundline dataset (docs/dataset.md) through the causal localizer
(the same code `groundline serve` runs) and estimates T_map_base.

Modes:
  odometry  dead reckoning of the wheel encoders (differential drive, covariance
            growing with distance and rotation; keyframes every 0.20 m or 5 deg):
            the odometry-only baseline row of every accuracy table.
  lines     floor lines (camera -> BEV -> lines) + odometry in the sliding-window
            smoother on the atlas (--atlas, default the dataset's floor map, whose
            wall and rack faces become face lines); with --lidar also the LiDAR
            scan-match factor between keyframes, which keeps only the directions
            the scan constrains (not along an aisle), and the scans' straight
            faces as line observations against the atlas' faces. With
            --atlas-out FILE it also keeps the atlas current: a marking that
            matches nothing is tracked and becomes a landmark after 3
            consistent sightings; one that should be in the camera's view and
            is not seen 10 keyframes in a row is retired; FILE gets the atlas
            with both (docs/atlas.md, "Keeping the atlas current").
  mapping   the same, building the atlas (--atlas-out). With --lidar the atlas is
            of the whole drive: the LiDAR SLAM (submaps, loop closures) closes
            the trajectory, then floor lines, junctions and the wall and rack
            faces are solved jointly with it as landmarks, each with its
            covariance; the atlas is in the map frame of the start pose
            (docs/atlas.md, "Mapping with the LiDAR"), or with --surveyed FILE
            on the site's frame: a handful of surveyed markings far apart (a
            floor map .yaml with its survey block, or an atlas .json) that the
            built landmarks are tied to. Also writes trajectory_mapped.tum (the
            keyframes after the joint solve) and trajectory_mapped_lidar.tum
            (the LiDAR pose graph's, before it).
  lidar     LiDAR + odometry only: scan-to-submap matching with the odometry as
            the initial guess, keyframes every 0.20 m or 5 deg; health per
            keyframe: lidar_degenerate, the scaled information eigenvalues
            [1/m^2], the weakest direction (x, y, theta; also in the map frame).
  --carmen LOG  2D LiDAR + odometry SLAM (submaps, scan-to-submap matching,
            pose graph with loop closures) on a CARMEN log; writes trajectory.tum
            (one pose per front-laser scan, at its ipc_timestamp), health.jsonl and
            summary.json; with --relations FILE also the relation errors. Scans
            written out of order take their place by stamp if at most 1 s late;
            later ones and repeated stamps are dropped (counted and said).
            RAWLASER1 lines (no pose) get the ODOM lines' pose interpolated at
            their stamp, the laser placed by PARAM robot_frontlaser_offset.

Start pose: --initial-pose x_m y_m yaw_deg, else the manifest's start_pose (the
dock the vehicle starts from), else the map origin (with a warning).
--mode lines --relocalize instead recognizes it on the atlas: every junction the
camera sees, with a line through it, is matched against every atlas junction;
the candidates follow the odometry and are scored on later frames until one
leads every other by a margin (docs/atlas.md). A floor that repeats (identical
aisle mouths) stays ambiguous: --near x_m y_m [radius_m] says roughly where.

Odometry calibration: the manifest states the nominal wheel radius and track;
tyre wear and load change each wheel's effective radius by tenths of a percent,
which on a long aisle is decimetres. --mode lines --odometry-out FILE estimates,
after the run, each wheel's radius, the track and the wheel noise (with their
uncertainty) from the wheel readings against the trajectory localized on the
atlas (at least 20 segments of 2 m and one full turn in all; slips are left
out). --odometry FILE (or the service's localizer.odometry_calibration) then
uses them in place of the nominal geometry and the preset's noise
(docs/localization.md, "Odometry calibration").

The tuned values are the localizer's presets (docs/localization.md); the
--window, --gate-chi2, --slip-sigma, --wheel-variance and --lateral-variance
flags override them for experiments.

Writes into --out (created if missing; the files are written into a temporary
sibling folder and moved into --out at the end, so a run that fails leaves
--out as it was):
  trajectory.tum               keyframe poses, TUM 't x y z qx qy qz qw'
  trajectory_odometry_rate.tum one pose per encoder reading
  trajectory_covariance.txt    the keyframes' 3x3 covariances
  health.jsonl                 one JSON object per keyframe (docs/localization.md)
  summary.json                 counts of everything dropped or skipped, timings
                               (wall and CPU seconds, update median / p99, peak RSS),
                               and 'warnings': [{kind, message}] for a run that is not
                               what it seems (also printed): atlas_nearly_empty (a
                               mapping run whose atlas has < 4 floor lines is not
                               written and exits 1), stream_spans (streams that end or
                               start > 1 s apart), nees_out_of_band (mean NEES against
                               ground truth outside [0.3, 30]), skipped_lines,
                               scans_reordered, scans_dropped, laser_offset,
                               scans_without_odometry, odometry_dropped (--carmen)
With ground truth in the dataset it also prints the accuracy, in a block headed
'diagnostics (ground truth, not available on a vehicle)'; the full table:
groundline eval --est OUT/trajectory.tum --ref ...

Examples:
  groundline localize --dataset sample_zone_b --out run_odom
  groundline localize --dataset sample_zone_b --mode lines --lidar --out run_full
  groundline localize --dataset sample_zone_b --mode lines --relocalize --near 2 40 --out run_reloc
  groundline localize --dataset sample_zone_b --mode lidar --out run_lidar
  groundline localize --dataset survey_drive --mode mapping --lidar --atlas-out atlas.json --out run_map
  groundline localize --dataset survey_drive --mode mapping --lidar --surveyed site_lines.yaml --atlas-out atlas.json --out run_map
  groundline localize --dataset second_drive --mode lines --lidar --atlas atlas.json --out run_on_map
  groundline localize --dataset next_week --mode lines --lidar --atlas atlas.json --atlas-out atlas_kept.json --out run_kept
  groundline localize --dataset first_shift --mode lines --lidar --odometry-out odometry.json --out run_cal
  groundline localize --dataset next_shift --mode odometry --odometry odometry.json --out run_dr
  groundline localize --carmen aces.clf.bz2 --relations aces.relations --out run_aces)";

int Usage(const std::string& message) {
  std::fprintf(stderr, "groundline localize: %s\n", message.c_str());
  return 2;
}

loc::LocalizerOptions OptionsFromFlags(const LocalizeFlags& flags) {
  loc::LocalizerOptions options;  // odometry and LiDAR: the defaults
  if (flags.mode == "lines" || flags.mode == "mapping") {
    options = loc::LocalizerOptions::ForFusion();
    options.use_lidar = flags.lidar;
    options.mode =
        flags.mode == "mapping" ? loc::LocalizerMode::kMapping : loc::LocalizerMode::kLines;
    options.smoother.upkeep.enabled = flags.mode == "lines" && !flags.atlas_out_path.empty();
  } else {
    options.mode =
        flags.mode == "lidar" ? loc::LocalizerMode::kLidar : loc::LocalizerMode::kOdometry;
  }
  options.use_wall_lines = flags.wall_lines;
  options.smoother.solver =
      flags.solver == "ceres" ? loc::SmootherSolver::kCeres : loc::SmootherSolver::kChain;
  if (flags.window_s > 0.0) options.smoother.window_s = flags.window_s;
  if (flags.gate_chi2 > 0.0) options.smoother.association.gate_chi2 = flags.gate_chi2;
  if (flags.slip_sigma_m >= 0.0) options.smoother.slip_sigma_m = flags.slip_sigma_m;
  if (flags.wheel_variance_m2_per_m >= 0.0) {
    options.wheel_variance_m2_per_m = flags.wheel_variance_m2_per_m;
  }
  if (flags.lateral_variance_m2_per_m > 0.0) {
    options.lateral_variance_m2_per_m = flags.lateral_variance_m2_per_m;
  }
  if (flags.near.size() >= 2)
    options.relocalizer.near_m = Eigen::Vector2d(flags.near[0], flags.near[1]);
  if (flags.near.size() == 3) options.relocalizer.near_radius_m = flags.near[2];
  return options;
}

// Fewer lines than this cannot fix a pose (two crossing lines fix it only
// where both are seen): an atlas below it is unusable.
constexpr std::size_t kMinAtlasLines = 4;

int RunLocalize(const LocalizeFlags& flags) {
  const RunClock clock;
  core::DatasetReadOptions read_options;  // the image index, not the pixels; scans streamed
  read_options.check_image_files = false;
  read_options.load_scans = false;
  core::Result<core::Dataset> dataset = core::ReadDataset(flags.dataset_dir, read_options);
  if (!dataset.ok()) return LocalizeFail(dataset.message());
  const fs::path dir(flags.dataset_dir);

  service::DatasetLocalizerOptions setup_options;
  setup_options.localizer = OptionsFromFlags(flags);
  setup_options.atlas_path = flags.atlas_path;
  setup_options.surveyed_landmarks_path = flags.surveyed_path;
  setup_options.odometry_calibration_path = flags.odometry_path;
  if (!flags.odometry_path.empty() && flags.wheel_variance_m2_per_m >= 0.0) {
    return Usage("--wheel-variance: the odometry calibration " + flags.odometry_path +
                 " states the wheel noise; give one or the other");
  }
  if (!flags.odometry_out_path.empty() && flags.mode != "lines") {
    return Usage("--odometry-out " + flags.odometry_out_path +
                 ": the odometry is calibrated against a drive localized on an atlas, "
                 "--mode lines (with --lidar where the site has one), not --mode " +
                 flags.mode);
  }
  const loc::LocalizerOptions& options = setup_options.localizer;
  if (flags.relocalize && options.mode != loc::LocalizerMode::kLines) {
    return Usage("--relocalize needs an atlas to recognize: use it with --mode lines");
  }
  if (core::Status s = options.relocalizer.Validate(); !s.ok())
    return Usage("--near: " + s.message());
  if (!flags.atlas_out_path.empty() && options.mode != loc::LocalizerMode::kLines &&
      options.mode != loc::LocalizerMode::kMapping) {
    return Usage("--atlas-out " + flags.atlas_out_path +
                 ": an atlas is written by --mode mapping (built) or --mode lines (kept "
                 "current), not by --mode " +
                 flags.mode);
  }
  core::Result<service::DatasetSetup> setup =
      service::SetupFromDataset(dir, *dataset, setup_options);
  if (!setup.ok()) return LocalizeFail(setup.message());
  if (setup->setup.camera) {
    const perception::BevGrid& g = setup->setup.camera->remap().grid();
    std::printf("BEV: x %.2f..%.2f m, y %.2f..%.2f m (%d x %d cells)\n",
                g.FloorPointOfCell({0, g.rows() - 1}).x() - 0.5 * g.cell_m(),
                g.FloorPointOfCell({0, 0}).x() + 0.5 * g.cell_m(),
                g.FloorPointOfCell({g.cols() - 1, 0}).y() - 0.5 * g.cell_m(),
                g.FloorPointOfCell({0, 0}).y() + 0.5 * g.cell_m(), g.cols(), g.rows());
  }
  if (options.mode == loc::LocalizerMode::kLines) {
    std::printf("atlas: %zu lines (%d wall and rack faces), %zu junctions from %s\n",
                setup->setup.atlas.lines.size(), loc::CountWallLines(setup->setup.atlas),
                setup->setup.atlas.junctions.size(), setup->atlas_source.c_str());
  }
  std::optional<loc::KeyframeMountCalibration> self_calibration;
  if (flags.self_calibrate) {
    if (!setup->camera_mount) {
      return Usage("--self-calibrate needs the camera: use it with --mode lines or mapping");
    }
    loc::MountApplyOptions apply;
    apply.enabled = !flags.self_calibrate_report_only;
    setup->options.track_floor_texture = true;
    calibration::MountSelfCalibrationOptions self_calibration_options;
    if (setup->odometry_calibration) {
      self_calibration_options =
          loc::WithOdometryCalibration(self_calibration_options, *setup->odometry_calibration);
    }
    self_calibration.emplace(*setup->camera_mount, self_calibration_options, apply);
    if (setup->options.mode == loc::LocalizerMode::kLines) {
      self_calibration->SetAtlas(std::make_shared<const loc::Atlas>(setup->setup.atlas),
                                 setup->options.smoother.association);
    }
  }
  const loc::Atlas atlas_copy = setup->setup.atlas;
  const loc::DiffDriveParams drive_used = setup->setup.drive;
  if (setup->odometry_calibration) {
    const loc::OdometryCalibration& o = *setup->odometry_calibration;
    std::printf(
        "odometry: calibrated wheel radii %.5f / %.5f m, track %.4f m, wheel variance %.3g "
        "m^2/m from %s\n",
        o.drive.LeftRadius(), o.drive.RightRadius(), o.drive.track_m, o.wheel_variance_m2_per_m,
        flags.odometry_path.c_str());
  }
  core::Result<std::unique_ptr<loc::Localizer>> created =
      loc::Localizer::Create(setup->options, std::move(setup->setup));
  if (!created.ok()) return LocalizeFail(flags.dataset_dir + ": " + created.message());
  loc::Localizer& localizer = **created;

  std::string start_from;
  if (flags.relocalize) {
    if (core::Status s = localizer.RequestRelocalization(); !s.ok())
      return LocalizeFail(s.message());
    start_from = "relocalization on the atlas";
  } else {
    core::SE2 pose;
    double stamp_s = setup->first_reading_s;
    core::Matrix3 covariance = service::StartCovariance(core::StartPose{});
    if (flags.initial_pose.size() == 3) {
      pose = core::SE2(flags.initial_pose[0], flags.initial_pose[1],
                       flags.initial_pose[2] * std::numbers::pi / 180.0);
      start_from = "--initial-pose";
    } else if (setup->start_pose) {
      pose = setup->start_pose->T_map_base;
      stamp_s = std::min(stamp_s, setup->start_pose->stamp_s);
      covariance = service::StartCovariance(*setup->start_pose);
      start_from = "the manifest's start_pose";
    } else {
      start_from = "the map origin (no --initial-pose, no start_pose in the manifest)";
      std::fprintf(stderr, "groundline localize: warning: starting at the map origin\n");
    }
    if (core::Status s = localizer.SetInitialPose(stamp_s, pose, covariance); !s.ok()) {
      return LocalizeFail("--initial-pose: " + s.message());
    }
  }

  core::DatasetStreamOptions stream_options;  // only the streams the mode uses
  stream_options.frames = setup_options.localizer.mode == loc::LocalizerMode::kLines ||
                          setup_options.localizer.mode == loc::LocalizerMode::kMapping;
  stream_options.scans = options.mode == loc::LocalizerMode::kLidar || options.use_lidar;
  RunWarnings warnings("localize");
  {
    core::Result<std::vector<StreamSpan>> spans = StreamSpans(dir, *dataset, stream_options);
    if (!spans.ok()) return LocalizeFail(spans.message());
    CheckStreamSpans(*spans, &warnings);
  }
  if (options.mode == loc::LocalizerMode::kLines &&
      atlas_copy.lines.size() - loc::CountWallLines(atlas_copy) < kMinAtlasLines) {
    warnings.Add("atlas_nearly_empty",
                 "the atlas has " +
                     std::to_string(atlas_copy.lines.size() - loc::CountWallLines(atlas_copy)) +
                     " floor lines (fewer than " + std::to_string(kMinAtlasLines) +
                     " cannot fix a pose): the camera has next to nothing to localize against");
  }
  core::Result<core::DatasetStreams> streams =
      core::DatasetStreams::Open(dir, *dataset, stream_options);
  if (!streams.ok()) return LocalizeFail(streams.message());
  std::optional<LocalizeDiagnostics> diagnostics;
  if (flags.diagnose && !dataset->ground_truth.empty()) {
    diagnostics.emplace(dataset->ground_truth, atlas_copy, options.smoother.association);
  }
  core::Trajectory keyframes, odometry_rate;
  std::ostringstream health_lines;
  std::vector<double> update_ms, update_cpu_ms;
  ProgressLine progress("[localize]");
  const double t0 = setup->first_reading_s;
  const double t1 = dataset->wheel_encoders.back().stamp_s;
  const auto stored_covariance = [&](const loc::PoseEstimate& p) -> std::optional<core::Matrix3> {
    if (options.mode == loc::LocalizerMode::kLidar) return std::nullopt;
    return p.covariance;
  };
  // Row 0 of both trajectories is the start pose as the localizer took it
  // (after a relocalization: the committed pose).
  bool start_written = false;
  const auto write_start = [&] {
    if (start_written || !localizer.started()) return;
    start_written = true;
    const loc::PoseEstimate start = localizer.relocalized().value_or(localizer.Current());
    keyframes.push_back({start.stamp_s, start.T_map_base, stored_covariance(start)});
    odometry_rate.push_back(keyframes.back());
  };
  write_start();
  service::ReplayCallbacks callbacks;
  callbacks.on_keyframe = [&](const loc::KeyframeOutput& k) {
    write_start();
    nlohmann::ordered_json line = loc::KeyframeJson(k, options.mode);
    if (self_calibration) {
      self_calibration->AddKeyframe(k);
      if (const auto update = self_calibration->DueMountUpdate(k.stamp_s)) {
        if (core::Status s =
                localizer.SetCameraMount(update->mount, update->covariance, update->observed);
            !s.ok())
          std::fprintf(stderr, "warning: self-calibration: %s\n", s.message().c_str());
      }
      line.update(loc::MountEstimateJson(self_calibration->estimate(), &self_calibration->applied(),
                                         &self_calibration->observed()));
    }
    if (diagnostics) {
      line.update(diagnostics->BeforeUpdate(k.predicted, k.floor));
      line.update(diagnostics->AfterUpdate(k.pose));
    }
    health_lines << line.dump() << "\n";
    if (k.smoother) update_ms.push_back(1e3 * k.smoother->update_time_s);
    update_cpu_ms.push_back(1e3 * k.update_cpu_s);
    if (!k.error.empty()) {
      std::fprintf(stderr, "\ngroundline localize: keyframe at %.3f s: %s\n", k.stamp_s,
                   k.error.c_str());
    }
    keyframes.push_back({k.pose.stamp_s, k.pose.T_map_base,
                         k.has_covariance ? std::optional(k.pose.covariance) : std::nullopt});
  };
  callbacks.on_pose = [&](const loc::PoseEstimate& p) {
    write_start();
    if (p.stamp_s > odometry_rate.back().stamp_s) {
      odometry_rate.push_back({p.stamp_s, p.T_map_base, stored_covariance(p)});
    }
  };
  callbacks.on_progress = [&](double stamp_s) {
    progress.Update("replay", t1 > t0 ? (stamp_s - t0) / (t1 - t0) : 1.0);
  };
  service::ReplayOptions replay_options;
  replay_options.max_duration_s = flags.max_duration_s;
  core::Result<service::ReplayStats> replayed =
      service::Replay(*streams, localizer, replay_options, callbacks);
  progress.Update("replay", 1.0);
  if (!replayed.ok()) return LocalizeFail(replayed.message());
  if (flags.relocalize && !localizer.started()) {
    const loc::RelocalizerStatus* s = localizer.relocalizer_status();
    if (s != nullptr && s->hint_rejected && options.relocalizer.near_m) {
      return LocalizeFail(HintNotSupported(flags.dataset_dir, *options.relocalizer.near_m, *s));
    }
    return LocalizeFail(
        flags.dataset_dir + ": --relocalize: no unambiguous pose on the atlas after " +
        std::to_string(localizer.counters().frames_used) +
        " frames: " + std::to_string(s ? s->hypotheses : 0) + " hypotheses left from " +
        std::to_string(s ? s->seeds : 0) +
        " junction sightings; a repeating floor needs --near X_M Y_M [RADIUS_M] (where "
        "the drive starts), or give --initial-pose");
  }

  // Everything goes into a staging folder renamed into --out at the end: a
  // run that fails leaves no half-written folder.
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(flags.out_dir);
  if (!staged.ok()) return LocalizeFail(staged.message());
  const fs::path out = staged->path();
  const fs::path final_out(flags.out_dir);
  for (const core::Status& s :
       {core::WriteTumTrajectory(out / "trajectory.tum", keyframes),
        core::WriteTumTrajectory(out / "trajectory_odometry_rate.tum", odometry_rate),
        core::WriteTrajectoryCovariances(out / "trajectory_covariance.txt", keyframes),
        core::WriteFileAtomically(out / "health.jsonl", health_lines.str())}) {
    if (!s.ok()) return LocalizeFail(s.message());
  }
  const loc::LocalizerCounters& c = localizer.counters();
  nlohmann::ordered_json summary;
  summary["dataset"] = flags.dataset_dir;
  summary["mode"] = loc::ModeName(options);
  summary["started_from"] = start_from;
  summary["n_keyframes"] = keyframes.size();
  summary["n_odometry_poses"] = odometry_rate.size();
  summary["path_length_m"] = localizer.path_length_m();
  summary["frames_used"] = c.frames_used;
  summary["frames_skipped"] = c.frames_skipped;
  summary["images_unreadable"] = c.frames_unreadable;
  summary["solve_failures"] = c.solve_failures;
  summary["solves_unconverged"] = c.solves_unconverged;
  summary["lines_used"] = c.lines_used;
  summary["lines_rejected"] = c.lines_rejected;
  summary["lines_dropped"] = c.lines_dropped;
  summary["update_ms_median"] = Percentile(update_ms, 0.5);
  summary["update_ms_p99"] = Percentile(update_ms, 0.99);
  summary["update_cpu_ms_median"] = Percentile(update_cpu_ms, 0.5);
  summary["update_cpu_ms_p99"] = Percentile(update_cpu_ms, 0.99);
  summary["counters"] = loc::CountersJson(c);
  if (self_calibration) {
    const calibration::MountEstimate& e = self_calibration->estimate();
    nlohmann::ordered_json j =
        loc::MountEstimateJson(e, &self_calibration->applied(), &self_calibration->observed());
    j["frames"] = e.frames;
    j["frames_gated"] = e.frames_gated;
    j["windows_rejected"] = e.windows_rejected;
    j["windows_with_atlas"] = e.windows_with_atlas;
    j["mount_updates"] = self_calibration->mount_updates();
    summary["self_calibration"] = j;
    std::printf(
        "self-calibration: pitch %.3f deg, roll %.3f deg, height %.1f mm, yaw %.3f deg "
        "(%d windows of %d frames, %d steps)%s%s\n",
        e.mount.pitch_rad * core::kRadToDeg, e.mount.roll_rad * core::kRadToDeg,
        e.mount.height_m * 1e3, e.mount.yaw_rad * core::kRadToDeg, e.windows_used, e.frames,
        e.steps, e.alarm ? "; ALARM: " : "", e.alarm_message.c_str());
  }
  if (const std::optional<loc::PoseEstimate>& r = localizer.relocalized()) {
    summary["relocalized"] = RelocalizedJson(*r, localizer.relocalizer_status());
    std::printf("relocalized: %s\n", summary["relocalized"].dump().c_str());
  }
  std::printf(
      "%s: %zu keyframes (%ld camera frames used, %ld skipped, %ld unreadable), "
      "%ld lines used, %ld rejected; update %.2f ms median, %.2f ms p99; started at %s\n",
      flags.dataset_dir.c_str(), keyframes.size(), c.frames_used, c.frames_skipped,
      c.frames_unreadable, c.lines_used, c.lines_rejected, Percentile(update_ms, 0.5),
      Percentile(update_ms, 0.99), start_from.c_str());
  bool unusable = false;
  if (options.mode == loc::LocalizerMode::kMapping) {
    const fs::path atlas_out =
        flags.atlas_out_path.empty() ? out / "atlas.json" : fs::path(flags.atlas_out_path);
    const fs::path atlas_shown =
        flags.atlas_out_path.empty() ? final_out / "atlas.json" : atlas_out;
    loc::AtlasMapperReport report;
    ProgressLine building("[localize]");
    building.Update("building the atlas", 0.0);
    core::Result<loc::Atlas> built_or = localizer.BuildAtlas(&report);
    building.Update("building the atlas", 1.0);
    if (!built_or.ok()) return LocalizeFail(flags.dataset_dir + ": " + built_or.message());
    const loc::Atlas& built = *built_or;
    if (options.use_lidar) {
      summary["mapping"] = loc::AtlasMapperReportJson(report);
      std::printf(
          "mapping: %d keyframes, %d scans, %d loop closures (%d rejected); %ld sightings in "
          "the joint solve (%ld ambiguous left out), %d landmarks seen too rarely dropped; "
          "cost %.4g -> %.4g\n",
          report.keyframes, report.scans, report.loops, report.loops_rejected, report.sightings,
          report.sightings_ambiguous, report.landmarks_dropped, report.initial_cost,
          report.final_cost);
      for (const core::Status& s :
           {core::WriteTumTrajectory(out / "trajectory_mapped.tum", localizer.MappedTrajectory()),
            core::WriteTumTrajectory(out / "trajectory_mapped_lidar.tum",
                                     localizer.MappedTrajectory(true))}) {
        if (!s.ok()) return LocalizeFail(s.message());
      }
    }
    const std::size_t floor_lines = built.lines.size() - loc::CountWallLines(built);
    summary["atlas_lines"] = built.lines.size();
    summary["atlas_junctions"] = built.junctions.size();
    if (floor_lines < kMinAtlasLines) {
      unusable = true;
      warnings.Add("atlas_nearly_empty",
                   "the atlas built has " + std::to_string(floor_lines) + " floor lines and " +
                       std::to_string(built.junctions.size()) + " junctions (fewer than " +
                       std::to_string(kMinAtlasLines) + " lines cannot fix a pose), from " +
                       std::to_string(c.lines_used) + " lines used and " +
                       std::to_string(c.lines_rejected) + " rejected in " +
                       std::to_string(c.frames_used) +
                       " frames: not written. Drive over more markings, or check the camera "
                       "images and the mount (groundline extract)");
    } else {
      if (core::Status s = loc::WriteAtlas(atlas_out, built); !s.ok())
        return LocalizeFail(s.message());
      std::printf("atlas: %zu lines, %zu junctions -> %s\n", built.lines.size(),
                  built.junctions.size(), atlas_shown.string().c_str());
    }
  }
  if (options.smoother.upkeep.enabled) {
    const loc::Atlas kept = localizer.CurrentAtlas();
    summary["upkeep"] = {{"landmarks_born", c.landmarks_born},
                         {"landmarks_retired", c.landmarks_retired},
                         {"atlas_lines", kept.lines.size()},
                         {"atlas_junctions", kept.junctions.size()}};
    if (core::Status s = loc::WriteAtlas(flags.atlas_out_path, kept); !s.ok())
      return LocalizeFail(s.message());
    std::printf(
        "atlas kept current: %ld landmarks born, %ld retired; %zu lines, %zu junctions -> %s\n",
        c.landmarks_born, c.landmarks_retired, kept.lines.size(), kept.junctions.size(),
        flags.atlas_out_path.c_str());
  }
  bool calibration_failed = false;
  if (!flags.odometry_out_path.empty()) {
    loc::OdometryCalibrationOptions calibration_options;
    calibration_options.prior_wheel_variance_m2_per_m = setup->options.wheel_variance_m2_per_m;
    calibration_options.prior_lateral_variance_m2_per_m = setup->options.lateral_variance_m2_per_m;
    core::Result<loc::OdometryCalibration> calibrated =
        loc::CalibrateOdometry(dataset->wheel_encoders, drive_used, keyframes, calibration_options);
    if (calibrated.ok()) {
      calibrated->drive.wheel_radius_m = dataset->manifest.wheel_encoders->wheel_radius_m;
      calibrated->source = flags.dataset_dir;
      if (core::Status s = loc::WriteOdometryCalibration(flags.odometry_out_path, *calibrated);
          !s.ok()) {
        return LocalizeFail(s.message());
      }
      const core::Vector3 sigma = calibrated->drive_covariance.diagonal().cwiseSqrt();
      summary["odometry_calibration"] = {
          {"file", flags.odometry_out_path},
          {"left_wheel_radius_m", calibrated->drive.LeftRadius()},
          {"right_wheel_radius_m", calibrated->drive.RightRadius()},
          {"track_m", calibrated->drive.track_m},
          {"sigma_m", {sigma(0), sigma(1), sigma(2)}},
          {"wheel_variance_m2_per_m", calibrated->wheel_variance_m2_per_m},
          {"lateral_variance_m2_per_m", calibrated->lateral_variance_m2_per_m},
          {"segments", calibrated->segments},
          {"segments_rejected", calibrated->segments_rejected}};
      std::printf(
          "odometry calibrated from %d segments (%.0f m, %.0f deg of turns; %d left out): "
          "wheel radii %.5f / %.5f m (+-%.5f), track %.4f m (+-%.4f), wheel variance %.3g "
          "m^2/m -> %s\n",
          calibrated->segments, calibrated->distance_m, calibrated->rotation_rad * core::kRadToDeg,
          calibrated->segments_rejected, calibrated->drive.LeftRadius(),
          calibrated->drive.RightRadius(), sigma(0), calibrated->drive.track_m, sigma(2),
          calibrated->wheel_variance_m2_per_m, flags.odometry_out_path.c_str());
    } else {
      calibration_failed = true;
      summary["odometry_calibration"] = {{"error", calibrated.message()}};
      std::fprintf(stderr, "groundline localize: %s (no %s written)\n",
                   calibrated.message().c_str(), flags.odometry_out_path.c_str());
    }
  }
  if (core::Status s = FinishRunSummary(keyframes, dataset->ground_truth,
                                        options.mode != loc::LocalizerMode::kLidar, clock, out,
                                        &warnings, &summary);
      !s.ok()) {
    return LocalizeFail(s.message());
  }
  if (core::Status s = staged->Commit(); !s.ok()) return LocalizeFail(s.message());
  if (warnings.size() > 0) {
    std::fprintf(stderr, "groundline localize: %zu warning%s (listed in %s)\n", warnings.size(),
                 warnings.size() == 1 ? "" : "s", (final_out / "summary.json").string().c_str());
  }
  return unusable || calibration_failed ? 1 : 0;
}

}  // namespace

CLI::App* AddLocalizeCommand(CLI::App& parent, CommandRunner* run) {
  auto flags = std::make_shared<LocalizeFlags>();
  CLI::App* cmd = parent.add_subcommand("localize", "Estimate the vehicle pose from a dataset");
  cmd->footer(kLocalizeHelp);
  cmd->add_option("-d,--dataset", flags->dataset_dir, "Dataset directory (docs/dataset.md)")
      ->check(CLI::ExistingDirectory);
  auto carmen = std::make_shared<LocalizeCarmenFlags>();
  cmd->add_option("--carmen", carmen->log_path,
                  "CARMEN log (.clf[.gz|.bz2]): 2D LiDAR + odometry SLAM instead of --dataset")
      ->check(CLI::ExistingFile)
      ->excludes("--dataset");
  cmd->add_option("--relations", carmen->relations_path,
                  "With --carmen: Kuemmerle .relations file to score the trajectory against")
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", flags->out_dir, "Output directory for the run")->required();
  cmd->add_option("--mode", flags->mode, "Estimator")
      ->check(CLI::IsMember({"odometry", "lines", "mapping", "lidar"}))
      ->capture_default_str();
  cmd->add_option("--initial-pose", flags->initial_pose, "Start pose: x_m y_m yaw_deg")
      ->expected(3);
  cmd->add_option("--atlas", flags->atlas_path,
                  "--mode lines: the atlas to localize on (default: the dataset's floor map)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--surveyed", flags->surveyed_path,
                  "--mode mapping --lidar: surveyed landmarks in the site frame (a floor map "
                  ".yaml of a few markings far apart, or an atlas .json) that tie the built "
                  "atlas to the site")
      ->check(CLI::ExistingFile);
  cmd->add_option("--atlas-out", flags->atlas_out_path,
                  "--mode mapping: where to write the atlas (default OUT/atlas.json); --mode "
                  "lines: keep the atlas current (new markings born, vanished ones retired) "
                  "and write it there");
  cmd->add_option("--odometry", flags->odometry_path,
                  "The vehicle's odometry calibration (--odometry-out of an earlier run): "
                  "each wheel's radius, the track and the wheel noise in place of the "
                  "manifest's nominal geometry and the preset's noise; with --self-calibrate "
                  "its uncertainty is the motion's scale and curvature error, which sets how "
                  "well the camera's height and yaw are known")
      ->check(CLI::ExistingFile);
  cmd->add_option("--odometry-out", flags->odometry_out_path,
                  "--mode lines: after the run, calibrate the odometry (wheel radii, track, "
                  "wheel noise, with their uncertainty) against the localized trajectory and "
                  "write it here (JSON; the service reads it as localizer.odometry_calibration)");
  cmd->add_flag("--diagnose", flags->diagnose,
                "--mode lines: with ground truth, add per-keyframe errors (along/across track, "
                "heading) and an association check (right/wrong/missed lines) to health.jsonl "
                "(evaluation only)");
  cmd->add_option("--wheel-variance", flags->wheel_variance_m2_per_m,
                  "--mode lines/mapping: override the preset's odometry noise: independent "
                  "wheel errors of this variance per metre of wheel travel [m^2/m] (0: the "
                  "OdometryNoiseParams defaults)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--lateral-variance", flags->lateral_variance_m2_per_m,
                  "--mode lines/mapping: override the preset's lateral odometry variance per "
                  "metre travelled [m^2/m] (> 0)")
      ->check(CLI::Range(1e-12, 1.0));
  cmd->add_option("--slip-sigma", flags->slip_sigma_m,
                  "--mode lines: override the preset's RMS spurious travel of a wheel slip [m] "
                  "for the association gate's slip hypothesis (0: off)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--gate-chi2", flags->gate_chi2,
                  "--mode lines/mapping: override the association gate on the Mahalanobis "
                  "distance of a line (chi-square, 2 dof; preset 9.21 = 0.99 quantile)")
      ->check(CLI::Range(0.1, 1000.0));
  cmd->add_option("--window", flags->window_s,
                  "--mode lines/mapping: override the sliding-window length, seconds (preset 120)")
      ->check(CLI::Range(1.0, 3600.0));
  cmd->add_flag("--relocalize", flags->relocalize,
                "--mode lines: find the start pose on the atlas from a junction and the lines "
                "around it (no --initial-pose used)");
  cmd->add_option("--near", flags->near,
                  "With --relocalize: x_m y_m [radius_m] where the drive starts (default radius "
                  "2 m); needed where the floor repeats (identical aisle mouths)")
      ->expected(2, 3);
  CLI::Option* self_calibrate =
      cmd->add_flag("--self-calibrate", flags->self_calibrate,
                    "--mode lines/mapping: estimate the camera's pitch, roll, height and yaw from "
                    "the floor lines while driving (parallel and perpendicular markings, the "
                    "markings' motion against the wheel odometry); health.jsonl gets selfcal_* "
                    "fields per keyframe, summary.json the final estimate and any alarm; the "
                    "bird's-eye view follows the estimate in bounded steps");
  cmd->add_flag("--self-calibrate-report-only", flags->self_calibrate_report_only,
                "With --self-calibrate: estimate and report, but keep the bird's-eye view on "
                "the commissioned mount (to compare)")
      ->needs(self_calibrate);
  cmd->add_flag("--lidar", flags->lidar,
                "--mode lines/mapping: add the LiDAR scan-match factor (needs lidar_scans) and, "
                "when localizing, the straight faces (rack faces, walls) of the scans as line "
                "observations against the atlas' face lines");
  cmd->add_flag("--no-wall-lines{false}", flags->wall_lines,
                "--mode lines --lidar: no wall lines (only the scan-match factor)");
  cmd->add_option("--solver", flags->solver,
                  "--mode lines: window solver, chain (exact block elimination of the pose "
                  "chain) or ceres (Levenberg-Marquardt, the reference)")
      ->check(CLI::IsMember({"chain", "ceres"}))
      ->capture_default_str();
  cmd->add_option("--max-duration", flags->max_duration_s,
                  "Replay only this many seconds of data after the first reading (0: all), "
                  "e.g. --max-duration 150")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  cmd->callback([flags, carmen, run] {
    CheckLocalizeFlags(flags->relocalize, flags->mode, flags->initial_pose, flags->near);
    if (!carmen->log_path.empty()) {
      carmen->out_dir = flags->out_dir;
      *run = [carmen] { return RunLocalizeCarmen(*carmen); };
      return;
    }
    if (flags->dataset_dir.empty()) throw CLI::RequiredError("--dataset or --carmen");
    *run = [flags] { return RunLocalize(*flags); };
  });
  return cmd;
}

}  // namespace groundline::tools
