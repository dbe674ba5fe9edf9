// Keyframes come from camera frames: a frame becomes a keyframe when the
// vehicle has moved 0.20 m or turned 5 deg since the last one (other frames
// are skipped); without camera frames, an odometry-only keyframe every
// 1.0 m keeps the chain going. The keyframe is stamped at the encoder reading
// that closes the frame's interval (the frame's own stamp is in health.jsonl);
// unreadable images are named, counted and replaced by an empty observation.
#include "localize_lines.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/trajectory_covariance_io.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/core/trajectory_metrics.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/atlas_walls.h"
#include "groundline/localization/keyframe_selector.h"
#include "groundline/localization/observations_from_extraction.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/localization/sliding_window_smoother.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/line_extractor.h"
#include "localize_diagnostics.h"
#include "localize_lidar.h"
#include "localize_relocalize.h"
#include "localize_walls.h"
#include "progress.h"
#include "run_summary.h"

namespace groundline::tools {
namespace {

namespace fs = std::filesystem;

constexpr double kOdometryOnlyKeyframeM = 1.0;

int Fail(const std::string& message) {
  std::fprintf(stderr, "groundline localize: %s\n", message.c_str());
  return 1;
}

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t k = static_cast<std::size_t>(q * static_cast<double>(values.size() - 1) + 0.5);
  return values[std::min(k, values.size() - 1)];
}

// The extractor for the smoother. Its line covariances are those of one frame
// (issue 4's NEES); the smoother treats frames as independent, but a bias
// that a scuff, a stain or wear puts on a line persists over every frame
// that sees it. So the covariance here keeps one correlation length for the
// scatter and the mean (4 sqrt(pi) sigma, 3-4x the per-frame alpha variance)
// and no rho floor: with the per-frame model (docs/perception.md), zone A's
// NEES in band fell from 91.1 to 89.9 %. Its alpha floor is 0.04 deg about the
// foot of the origin (diag floor), as tuned then; the per-frame model's
// centroid floors (0.4 mm, 0.03 deg) took zone A's pose NEES in band from
// 91.4 to 81.6 %: a few millimetres of sideways play at the line, which the
// smoother needs for the biases that persist over frames.
perception::LineExtractorOptions FusionExtractorOptions() {
  perception::LineExtractorOptions options;
  options.correlation_samples = options.ScatterCorrelationSamples();
  options.rho_floor_m = 0.0;
  options.alpha_floor_rad = 0.0007;  // 0.04 deg
  options.floor_about_centroid = false;
  return options;
}

// The BEV grid (1 cm cells) over the floor the camera sees: the bounding box
// of the valid cells of a coarse 2 cm grid over 0-6 m ahead, +-4 m across.
// The default BevGridOptions (+-1.0 m) cut off the far corners of the
// footprint (+-1.3 m), where zone B's aisle boundary tapes are seen.
perception::BevGridOptions BevGridCoveringCamera(const calibration::CameraModel& camera,
                                                 const calibration::CameraMount& mount) {
  perception::BevRemap::Options coarse;
  coarse.grid = {0.0, 6.0, -4.0, 4.0, 0.02};
  const perception::BevRemap probe(camera, mount, coarse);
  std::vector<cv::Point> valid;
  cv::findNonZero(probe.valid_mask(), valid);
  perception::BevGridOptions grid;
  if (valid.empty()) return grid;  // nothing seen: keep the default extent
  const cv::Rect box = cv::boundingRect(valid);
  const perception::BevGrid& g = probe.grid();
  // Row 0 is the far edge (x_max), column 0 the left edge (y_max).
  const Eigen::Vector2d far_left = g.FloorPointOfCell(Eigen::Vector2d(box.x, box.y));
  const Eigen::Vector2d near_right =
      g.FloorPointOfCell(Eigen::Vector2d(box.x + box.width - 1, box.y + box.height - 1));
  const double margin_m = g.cell_m();
  grid.x_max_m = far_left.x() + margin_m;
  grid.y_max_m = far_left.y() + margin_m;
  grid.x_min_m = std::max(0.0, near_right.x() - margin_m);
  grid.y_min_m = near_right.y() - margin_m;
  return grid;
}

core::Result<localization::Atlas> LoadAtlas(const LocalizeLinesFlags& flags,
                                            const core::Dataset& dataset) {
  if (flags.mapping) return localization::Atlas();
  if (!flags.atlas_path.empty()) return localization::ReadAtlas(flags.atlas_path);
  if (dataset.floor_map) {
    return localization::AtlasFromFloorMap(*dataset.floor_map,
                                           localization::AtlasFromFloorMapOptions());
  }
  return core::Status::Error(flags.dataset_dir +
                             ": --mode lines needs --atlas FILE or a dataset with floor_map.yaml");
}

nlohmann::ordered_json HealthLine(long keyframe, const localization::KeyframeHealth& health,
                                  const localization::PoseEstimate& pose,
                                  std::optional<double> frame_stamp_s, int dropped) {
  nlohmann::ordered_json line;
  line["keyframe"] = keyframe;
  line["stamp_s"] = pose.stamp_s;
  if (frame_stamp_s) line["frame_stamp_s"] = *frame_stamp_s;
  line["x_m"] = pose.T_map_base.x();
  line["y_m"] = pose.T_map_base.y();
  line["yaw_deg"] = pose.T_map_base.yaw() * 180.0 / std::numbers::pi;
  const core::Matrix3& c = pose.covariance;
  line["cov"] = {c(0, 0), c(0, 1), c(0, 2), c(1, 0), c(1, 1), c(1, 2), c(2, 0), c(2, 1), c(2, 2)};
  line["lines_observed"] = health.lines_observed;
  line["lines_used"] = health.lines_used;
  line["lines_rejected"] = health.lines_rejected;
  line["lines_ambiguous"] = health.lines_ambiguous;
  line["lines_dropped"] = dropped;
  line["junctions_used"] = health.junctions_used;
  if (health.slip_gate) line["slip_gate"] = true;
  line["landmarks_added"] = health.landmarks_added;
  line["window_size"] = health.window_size;
  line["iterations"] = health.iterations;
  line["converged"] = health.converged;
  line["solve_ms"] = 1e3 * health.solve_time_s;
  line["update_ms"] = 1e3 * health.update_time_s;
  return line;
}

// CPU seconds of the calling thread: the update's own time, without the
// time the thread waited for a core (wall time on a loaded machine).
double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

int RunLocalizeLines(const LocalizeLinesFlags& flags) {
  const RunClock clock;
  core::DatasetReadOptions read_options;  // the image index, not the pixels
  read_options.check_image_files = false;
  read_options.load_scans = false;
  core::Result<core::Dataset> dataset = core::ReadDataset(flags.dataset_dir, read_options);
  if (!dataset.ok()) return Fail(dataset.message());
  const core::DatasetManifest& manifest = dataset->manifest;
  if (!manifest.wheel_encoders || dataset->wheel_encoders.empty()) {
    return Fail(flags.dataset_dir + ": the lines modes need wheel encoder readings");
  }
  if (!manifest.camera) return Fail(flags.dataset_dir + ": the lines modes need a camera");
  const fs::path dir(flags.dataset_dir);
  core::Result<calibration::CameraModel> camera =
      calibration::ReadCameraModel(dir / manifest.camera->intrinsics_file);
  if (!camera.ok()) return Fail(camera.message());
  core::Result<calibration::CameraMount> mount =
      calibration::ReadCameraMountYaml(dir / manifest.camera->extrinsics_file);
  if (!mount.ok()) return Fail(mount.message());
  core::Result<localization::Atlas> atlas = LoadAtlas(flags, *dataset);
  if (!atlas.ok()) return Fail(atlas.message());
  // Wall lines: the atlas' own, else the simulated zone's faces; without
  // either the run goes on without them (a warning, not a failure).
  bool use_walls = flags.lidar && flags.wall_lines && !flags.mapping;
  if (use_walls && localization::CountWallLines(*atlas) == 0) {
    core::Result<std::vector<localization::WallSegment>> walls = SimulatedWallSegments(*dataset);
    core::Status added =
        walls.ok() ? localization::AppendWallLines(*walls, {}, &*atlas) : walls.status();
    if (added.ok()) {
      const auto rack_faces =
          std::count_if(walls->begin(), walls->end(), [](const auto& w) { return w.rack_face; });
      std::printf("atlas: %zu wall lines from the simulated zone's faces (%td rack faces)\n",
                  walls->size(), rack_faces);
    } else {
      std::fprintf(stderr, "groundline localize: %s: no wall lines: %s\n",
                   flags.dataset_dir.c_str(), added.message().c_str());
      use_walls = false;
    }
  }

  perception::BevRemap::Options remap_options = perception::BevRemap::Options::ForLineExtraction();
  remap_options.grid = BevGridCoveringCamera(*camera, *mount);
  const perception::BevRemap remap(*camera, *mount, remap_options);
  std::printf("BEV: x %.2f..%.2f m, y %.2f..%.2f m (%d x %d cells)\n", remap_options.grid.x_min_m,
              remap_options.grid.x_max_m, remap_options.grid.y_min_m, remap_options.grid.y_max_m,
              remap.grid().cols(), remap.grid().rows());
  const perception::LineExtractor extractor(remap, FusionExtractorOptions());

  localization::DiffDriveParams drive;
  drive.wheel_radius_m = manifest.wheel_encoders->wheel_radius_m;
  drive.track_m = manifest.wheel_encoders->track_m;
  localization::OdometryNoiseParams noise;
  if (flags.wheel_variance_m2_per_m > 0.0) {
    noise = localization::OdometryNoiseFromWheelVariance(
        flags.wheel_variance_m2_per_m, drive.track_m, flags.lateral_variance_m2_per_m);
  }
  const fs::path index_dir = (dir / manifest.files.image_index).parent_path();

  // Start pose: --relocalize (recognized on the atlas), --initial-pose, the
  // first ground-truth pose, else the origin.
  double start_s = dataset->wheel_encoders.front().stamp_s;
  core::SE2 start_pose;
  core::Matrix3 start_covariance =
      core::Vector3(0.005 * 0.005, 0.005 * 0.005, std::pow(0.1 * std::numbers::pi / 180.0, 2))
          .asDiagonal();
  nlohmann::ordered_json relocalized;
  if (flags.relocalize && flags.mapping) {
    return Fail("--relocalize needs an atlas to recognize: use it with --mode lines");
  }
  if (flags.relocalize) {
    localization::RelocalizerOptions options;
    if (flags.near.size() >= 2) options.near_m = Eigen::Vector2d(flags.near[0], flags.near[1]);
    if (flags.near.size() == 3) options.near_radius_m = flags.near[2];
    if (core::Status s = options.Validate(); !s.ok()) return Fail("--near: " + s.message());
    core::Result<RelocalizedStart> found =
        RelocalizeOnAtlas(*dataset, index_dir, remap, extractor, drive, noise, *atlas, options);
    if (!found.ok()) return Fail(flags.dataset_dir + ": " + found.message());
    start_s = found->pose.stamp_s;
    start_pose = found->pose.T_map_base;
    start_covariance = found->pose.covariance;
    relocalized = RelocalizationSummary(*found, dataset->ground_truth);
    std::printf("relocalized: %s\n", relocalized.dump().c_str());
  } else if (flags.initial_pose.size() == 3) {
    start_pose = core::SE2(flags.initial_pose[0], flags.initial_pose[1],
                           flags.initial_pose[2] * std::numbers::pi / 180.0);
  } else if (!dataset->ground_truth.empty()) {
    start_s = dataset->ground_truth.front().stamp_s;
    start_pose = dataset->ground_truth.front().pose;
  }

  localization::OdometryIntegrator integrator(drive, noise);
  const localization::KeyframeSelector selector{localization::KeyframeSelector::Options()};
  localization::SmootherOptions smoother_options;
  smoother_options.mode = flags.mapping ? localization::SmootherMode::kMapping
                                        : localization::SmootherMode::kLocalization;
  smoother_options.window_s = flags.window_s;
  smoother_options.association.gate_chi2 = flags.gate_chi2;
  smoother_options.slip_sigma_m = flags.slip_sigma_m;
  smoother_options.track_m = drive.track_m;
  smoother_options.solver = flags.solver == "ceres" ? localization::SmootherSolver::kCeres
                                                    : localization::SmootherSolver::kChain;
  std::optional<LocalizeDiagnostics> diagnostics;
  if (flags.diagnose && !dataset->ground_truth.empty()) {
    diagnostics.emplace(dataset->ground_truth, *atlas, smoother_options.association);
  }
  std::optional<WallLineSource> walls;  // --lidar: rack faces and walls as lines
  if (use_walls) walls.emplace(*dataset, *atlas, smoother_options.association);
  localization::SlidingWindowSmoother smoother(smoother_options, std::move(*atlas));
  smoother.Initialize(start_s, start_pose, start_covariance);
  std::unique_ptr<LidarKeyframeSource> lidar;  // --lidar: the scan-match factor
  if (flags.lidar) {
    auto opened = LidarKeyframeSource::Open(dir, *dataset, {start_s, start_pose, std::nullopt});
    if (!opened.ok()) return Fail(opened.message());
    lidar = std::move(*opened);
  }

  core::Trajectory keyframes{{start_s, start_pose, start_covariance}};
  core::Trajectory odometry_rate{{start_s, start_pose, start_covariance}};
  std::ostringstream health_lines;
  std::vector<double> update_ms;
  std::vector<double> update_cpu_ms;  // the updating thread's CPU time
  long frames_used = 0, frames_skipped = 0, images_unreadable = 0, solve_failures = 0;
  long solves_unconverged = 0;  // stopped at max_iterations
  long lines_used = 0, lines_rejected = 0, lines_dropped = 0;
  const std::vector<core::ImageRecord>& images = dataset->images;
  std::size_t next_image = 0;
  while (next_image < images.size() && images[next_image].stamp_s < start_s) ++next_image;

  ProgressLine progress("[localize]");
  const std::vector<core::WheelEncoderReading>& readings = dataset->wheel_encoders;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const core::WheelEncoderReading& r = readings[i];
    if (r.stamp_s <= start_s) continue;
    if (flags.max_duration_s > 0.0 && r.stamp_s > start_s + flags.max_duration_s) break;
    if (i % 1000 == 0) progress.Update("replay", static_cast<double>(i) / readings.size());
    integrator.Integrate(localization::WheelAngleIncrement{r.left_delta_rad, r.right_delta_rad});
    std::optional<std::size_t> frame;
    while (next_image < images.size() && images[next_image].stamp_s <= r.stamp_s + 1e-9) {
      frame = next_image++;
    }
    const localization::RelativeMotion& since = integrator.SinceKeyframe();
    const bool moved = selector.IsKeyframeDue(since.T_start_end);
    const bool blind = since.path_length_m >= kOdometryOnlyKeyframeM;
    if (frame && !moved) ++frames_skipped;
    if ((frame && moved) || blind) {
      localization::ConvertedObservations converted;
      converted.observations.stamp_s = r.stamp_s;
      if (frame) {
        std::optional<localization::ConvertedObservations> seen =
            ObservationsOfImage(index_dir / images[*frame].file, r.stamp_s, remap, extractor);
        if (seen) {
          converted = std::move(*seen);
          ++frames_used;
        } else {
          ++images_unreadable;
        }
      }
      const localization::RelativeMotion motion = integrator.StartKeyframe();
      nlohmann::ordered_json diagnosis;
      if (diagnostics) {
        diagnosis = diagnostics->BeforeUpdate(
            localization::PropagateFromKeyframe(smoother.Latest(), motion, r.stamp_s),
            converted.observations);
      }
      std::optional<localization::lidar::ScanOdometryKeyframe> scan_match;
      if (lidar) {
        auto k = lidar->KeyframeAt(r.stamp_s);
        if (!k.ok()) return Fail(k.message());
        scan_match = std::move(*k);
      }
      nlohmann::ordered_json wall_health;
      if (walls) {
        const std::vector<localization::LineObservation> seen = walls->Observe(
            *lidar, r.stamp_s,
            localization::PropagateFromKeyframe(smoother.Latest(), motion, r.stamp_s),
            &wall_health);
        converted.observations.lines.insert(converted.observations.lines.end(), seen.begin(),
                                            seen.end());
      }
      const double cpu_before_s = ThreadCpuSeconds();
      core::Result<localization::KeyframeHealth> health =
          smoother.AddKeyframe(r.stamp_s, motion, converted.observations,
                               scan_match ? scan_match->relative : std::nullopt);
      if (!health.ok()) {
        ++solve_failures;
        std::fprintf(stderr, "\ngroundline localize: keyframe at %.3f s: %s\n", r.stamp_s,
                     health.message().c_str());
      } else {
        update_ms.push_back(1e3 * health->update_time_s);
        update_cpu_ms.push_back(1e3 * (ThreadCpuSeconds() - cpu_before_s));
        lines_used += health->lines_used;
        solves_unconverged += health->converged ? 0 : 1;
        lines_rejected += health->lines_rejected;
        lines_dropped += converted.dropped_lines;
        nlohmann::ordered_json line = HealthLine(
            static_cast<long>(keyframes.size()), *health, smoother.Latest(),
            frame ? std::optional(images[*frame].stamp_s) : std::nullopt, converted.dropped_lines);
        line["update_cpu_ms"] = update_cpu_ms.back();
        if (diagnostics) {
          line.update(diagnosis);
          line.update(diagnostics->AfterUpdate(smoother.Latest()));
        }
        if (scan_match) lidar->AddHealth(*scan_match, &line);
        if (walls) line.update(wall_health);
        health_lines << line.dump() << "\n";
      }
      const localization::PoseEstimate& latest = smoother.Latest();
      keyframes.push_back({latest.stamp_s, latest.T_map_base, latest.covariance});
    }
    const localization::PoseEstimate now = localization::PropagateFromKeyframe(
        smoother.Latest(), integrator.SinceKeyframe(), r.stamp_s);
    odometry_rate.push_back({now.stamp_s, now.T_map_base, now.covariance});
  }
  progress.Update("replay", 1.0);

  const fs::path out(flags.out_dir);
  for (const core::Status& s :
       {core::WriteTumTrajectory(out / "trajectory.tum", keyframes),
        core::WriteTumTrajectory(out / "trajectory_odometry_rate.tum", odometry_rate),
        core::WriteTrajectoryCovariances(out / "trajectory_covariance.txt", keyframes),
        core::WriteFileAtomically(out / "health.jsonl", health_lines.str())}) {
    if (!s.ok()) return Fail(s.message());
  }
  nlohmann::ordered_json summary;
  summary["dataset"] = flags.dataset_dir;
  summary["mode"] = flags.mapping ? "mapping" : (flags.lidar ? "lines+lidar" : "lines");
  summary["solver"] = flags.mapping ? "ceres" : flags.solver;
  summary["n_keyframes"] = keyframes.size();
  summary["frames_used"] = frames_used;
  summary["frames_skipped"] = frames_skipped;
  summary["images_unreadable"] = images_unreadable;
  if (!relocalized.empty()) summary["relocalized"] = relocalized;
  summary["solve_failures"] = solve_failures;
  summary["solves_unconverged"] = solves_unconverged;
  summary["lines_used"] = lines_used;
  summary["lines_rejected"] = lines_rejected;
  summary["lines_dropped"] = lines_dropped;
  summary["update_ms_median"] = Percentile(update_ms, 0.5);
  summary["update_ms_p99"] = Percentile(update_ms, 0.99);
  summary["update_cpu_ms_median"] = Percentile(update_cpu_ms, 0.5);
  summary["update_cpu_ms_p99"] = Percentile(update_cpu_ms, 0.99);
  if (lidar) summary["lidar"] = lidar->Summary();
  if (walls) summary["walls"] = walls->Summary();
  std::printf(
      "%s: %zu keyframes (%ld camera frames used, %ld skipped, %ld unreadable), "
      "%ld lines used, %ld rejected; update %.2f ms median, %.2f ms p99\n",
      flags.dataset_dir.c_str(), keyframes.size(), frames_used, frames_skipped, images_unreadable,
      lines_used, lines_rejected, Percentile(update_ms, 0.5), Percentile(update_ms, 0.99));
  if (flags.mapping) {
    const fs::path atlas_out =
        flags.atlas_out_path.empty() ? out / "atlas.json" : fs::path(flags.atlas_out_path);
    const localization::Atlas built = smoother.CurrentAtlas();
    if (core::Status s = localization::WriteAtlas(atlas_out, built); !s.ok()) {
      return Fail(s.message());
    }
    std::printf("atlas: %zu lines, %zu junctions -> %s\n", built.lines.size(),
                built.junctions.size(), atlas_out.string().c_str());
  }
  if (core::Status s = FinishRunSummary(keyframes, dataset->ground_truth, clock, out, &summary);
      !s.ok()) {
    return Fail(s.message());
  }
  return 0;
}

}  // namespace groundline::tools
