// `groundline extract`: floor lines, junctions and their covariances of every
// image of a folder, a glob or a dataset (docs/perception.md).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "extract_output.h"
#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/ground_homography.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/statistics.h"
#include "groundline/core/trajectory_association.h"
#include "groundline/io/frame_source.h"
#include "groundline/perception/nuisance_truth.h"
#include "png_file.h"
#include "progress.h"

namespace groundline::tools {
namespace {

struct ExtractFlags {
  std::string input;
  std::string dataset;
  std::string camera;
  std::string extrinsics;
  std::string homography;
  std::string bev_uncertainty;
  std::vector<double> bev_x_m, bev_y_m;
  double bev_cell_m = perception::BevExtent{}.cell_m;
  std::string out;
  int png_every = 10;
  int max_frames = 0;
  double min_sigma_px = perception::LineExtractorOptions{}.min_sigma_px;
  double rho_floor_mm = 1e3 * perception::LineExtractorOptions{}.rho_floor_m;
  double alpha_floor_deg = perception::LineExtractorOptions{}.alpha_floor_rad * 180.0 / M_PI;
  bool single_bar_edges = perception::LineExtractorOptions{}.single_bar_edges;
  int supersampling = perception::BevRemap::Options::ForLineExtraction().supersampling;
  int supersampling_across =
      perception::BevRemap::Options::ForLineExtraction().supersampling_across;
  bool tape_occludes_joints = perception::VisibleLineOptions{}.tape_occludes_joints;
  double min_visible_run_m = perception::VisibleLineOptions{}.min_evaluated_run_m;
  double min_dark_contrast = perception::LineExtractorOptions{}.min_dark_side_contrast;
};

constexpr char kExtractHelp[] =
    R"(Extracts floor lines from camera images (docs/perception.md): each image is
mapped to a metric bird's-eye view (BEV: by default the floor the camera sees,
up to 30 m around its foot point where a pixel spans at most 3 cells, at 1 cm
cells; --bev-x, --bev-y and --bev-cell
set it) through the lens model and the mount, ridges are found with a
steerable filter, lines fitted by total least squares with sub-pixel ridge
centres, classified (tape = bright, joint = dark; longitudinal / transverse /
oblique) and paired into junctions.

Input: DIR (every .png/.jpg in it, sorted), a glob ('run/*.png', quoted), or
--dataset DIR (camera, extrinsics, images, ground truth and floor map from a
groundline dataset). Without --extrinsics the reference mount is used (0.58 m
high, pitched 42.4 deg down, 0.42 m ahead of the axle). --homography FILE takes
the mount from a ground homography instead (written out as mount.yaml, a
groundline extrinsics file): its floor frame becomes base_link. --bev-uncertainty
FILE (the bev_uncertainty.json of `calibrate floor`; default with --dataset:
the manifest's camera.bev_uncertainty_file, if any) raises each line's
covariance to at least what the calibration's own uncertainty leaves there.

Writes into --out:
  lines.jsonl    one object per image: image, ms (BEV + extraction time), lines
                 [rho_m, alpha_rad (Hesse normal form in base_link, rho >= 0),
                 cov (2x2 row-major covariance of rho [m] and alpha [rad]), kind,
                 start_m, end_m, length_m, bar (centre of two bar edges), edge
                 (the one visible edge of a wide bar), samples, rms_residual_m],
                 junctions [point_m, cov, lines, shape L/T/X]; with ground
                 truth also each line's truth
                 (marking_id, kind, edge, evaluated, error [d rho m, d alpha
                 rad] = line - truth in the line's (rho, alpha) description,
                 nees; null when unmatched), missed_marking_ids and
                 missed (visible markings 1.0-2.5 m ahead that no line
                 matched; missed: each true line in base_link). Visible: in
                 the search footprint, on a dash, and for a joint not under a
                 tape's paint (--tape-occludes-joints); evaluated when >= 30 cm
                 of it lies 1.0-2.5 m ahead, >= 20 cm of that unbroken
                 (--min-visible-run-m)
  bev_NAME.png, overlay_NAME.png   every --png-every-th frame (0: none), named
                 after the source image NAME.png/.jpg; the overlay's colours are
                 explained in a legend below it (and in docs/perception.md)
  mount.yaml     with --homography: the mount decomposed from it
  summary.json   frames, skipped (unreadable images, named on stderr),
                 ms_per_frame_median, bev (x_m, y_m, cell_m, rows, cols), mount
                 (source, height_m, pitch_deg, roll_deg, yaw_deg, forward_m,
                 lateral_m); with ground truth and a floor map also tpr,
                 fp_share, rho_err_median_m, alpha_err_median_deg and
                 nees_inside_95_band_share for lines 1.0-2.5 m ahead, overall and
                 per kind.

Example:
  groundline sim --zone B --length 89m --camera-rate 2 --no-lidar --out /tmp/b
  groundline extract --dataset /tmp/b --out /tmp/b-lines
  groundline extract 'frames/*.png' --camera cam.cameramodel --extrinsics mount.yaml --out x
  groundline extract road/ --camera info.yaml --homography robot.yaml --bev-x 0.1 0.6 --out y
Exit codes: 0 ok (also when some images were skipped), 1 unreadable camera,
extrinsics or dataset, or no image readable, 2 usage error.)";

struct Input {
  std::optional<calibration::CameraModel> camera;
  calibration::CameraMount mount;
  std::string mount_source = "the reference mount";  // for the summary
  std::vector<std::filesystem::path> images;
  std::vector<double> stamps_s;  // with a dataset
  core::Trajectory ground_truth;
  std::optional<core::FloorMap> floor_map;
  // A simulated dataset's nuisance truth (nuisance_truth.json), when present.
  std::optional<perception::NuisanceTruth> nuisance_truth;
  std::shared_ptr<const calibration::BevUncertaintyMap> bev_uncertainty;  // null: none
};

std::vector<std::filesystem::path> ListImages(const std::string& spec) {
  const std::vector<std::string> files = io::ListImageFiles(spec);
  return {files.begin(), files.end()};
}

core::Result<Input> LoadInput(const ExtractFlags& flags) {
  namespace fs = std::filesystem;
  std::string camera_path = flags.camera, extrinsics_path = flags.extrinsics;
  std::string bev_uncertainty_path = flags.bev_uncertainty;
  Input input;
  if (!flags.dataset.empty()) {
    core::DatasetReadOptions read;
    read.load_wheel_encoders = read.load_scans = false;
    read.check_image_files = false;
    core::Result<core::Dataset> dataset = core::ReadDataset(flags.dataset, read);
    if (!dataset.ok()) return core::Status::Error(dataset.message());
    if (!dataset->manifest.camera) {
      return core::Status::Error(flags.dataset + ": the dataset has no camera");
    }
    const fs::path dir(flags.dataset);
    if (camera_path.empty())
      camera_path = (dir / dataset->manifest.camera->intrinsics_file).string();
    if (extrinsics_path.empty() && flags.homography.empty()) {
      extrinsics_path = (dir / dataset->manifest.camera->extrinsics_file).string();
    }
    if (bev_uncertainty_path.empty() && !dataset->manifest.camera->bev_uncertainty_file.empty()) {
      bev_uncertainty_path = (dir / dataset->manifest.camera->bev_uncertainty_file).string();
    }
    const fs::path index_dir = (dir / dataset->manifest.files.image_index).parent_path();
    for (const core::ImageRecord& r : dataset->images) {
      input.images.push_back(index_dir / r.file);
      input.stamps_s.push_back(r.stamp_s);
    }
    input.ground_truth = std::move(dataset->ground_truth);
    input.floor_map = std::move(dataset->floor_map);
    if (const fs::path truth = dir / "nuisance_truth.json"; fs::exists(truth)) {
      core::Result<perception::NuisanceTruth> nuisances = perception::ReadNuisanceTruth(truth);
      if (!nuisances.ok()) return nuisances.status();
      input.nuisance_truth = std::move(nuisances).value();
    }
  } else {
    input.images = ListImages(flags.input);
    if (input.images.empty()) return core::Status::Error(flags.input + ": no images found");
  }
  if (camera_path.empty())
    return core::Status::Error("--camera FILE is required without --dataset");
  core::Result<calibration::CameraModel> camera = calibration::ReadCameraModel(camera_path);
  if (!camera.ok()) return core::Status::Error(camera.message());
  input.camera = std::move(*camera);
  if (!flags.homography.empty()) {
    core::Result<calibration::GroundHomography> h =
        calibration::ReadGroundHomographyYaml(flags.homography);
    if (!h.ok()) return h.status();
    // A legacy file maps rectified pixels: it needs the rectified image's
    // pinhole matrix, the left 3x3 of camera_info's P.
    Eigen::Matrix3d K_rectified = input.camera->K();
    if (h->input == calibration::HomographyInput::kRectifiedPixel) {
      core::Result<calibration::RosCameraInfo> info = calibration::ReadRosCameraInfo(camera_path);
      if (!info.ok()) {
        return core::Status::Error(
            flags.homography +
            ": this homography maps rectified pixels; --camera must be the ROS camera_info "
            "YAML of that rectification (its projection_matrix P), but " +
            info.message());
      }
      K_rectified = info->projection.leftCols<3>();
    }
    core::Result<calibration::GroundHomographyMount> mount =
        calibration::MountFromGroundHomography(*h, K_rectified);
    if (!mount.ok()) return mount.status().WithContext(flags.homography);
    input.mount = mount->mount;
    input.mount_source = flags.homography;
    if (mount->mirrored_y) {
      input.mount_source += " (its left-handed floor frame mirrored in y)";
    }
  } else if (!extrinsics_path.empty()) {
    core::Result<calibration::CameraMount> mount =
        calibration::ReadCameraMountYaml(extrinsics_path);
    if (!mount.ok()) return core::Status::Error(mount.message());
    input.mount = *mount;
    input.mount_source = extrinsics_path;
  }
  if (!bev_uncertainty_path.empty()) {
    core::Result<calibration::BevUncertaintyMap> map =
        calibration::ReadBevUncertaintyMap(bev_uncertainty_path);
    if (!map.ok()) return map.status();
    if (core::Status s =
            calibration::CheckBevUncertaintyCamera(*map, *input.camera, bev_uncertainty_path);
        !s.ok()) {
      return s;
    }
    input.bev_uncertainty =
        std::make_shared<const calibration::BevUncertaintyMap>(std::move(map).value());
  }
  return input;
}

// T_map_base at stamp_s, interpolated; nullopt outside the trajectory.
std::optional<core::SE2> PoseAt(const core::Trajectory& trajectory, double stamp_s) {
  auto after = std::lower_bound(trajectory.begin(), trajectory.end(), stamp_s,
                                [](const core::StampedPose& p, double t) { return p.stamp_s < t; });
  if (after == trajectory.end() || (after == trajectory.begin() && after->stamp_s > stamp_s)) {
    return std::nullopt;
  }
  if (after->stamp_s == stamp_s || after == trajectory.begin()) return after->pose;
  const auto before = after - 1;
  const double f = (stamp_s - before->stamp_s) / (after->stamp_s - before->stamp_s);
  return core::InterpolateSE2(before->pose, after->pose, f);
}

int RunExtract(const ExtractFlags& flags) {
  namespace fs = std::filesystem;
  core::Result<Input> input = LoadInput(flags);
  if (!input.ok()) {
    std::fprintf(stderr, "groundline extract: %s\n", input.message().c_str());
    return 1;
  }
  perception::LineExtractorOptions options;
  options.min_sigma_px = flags.min_sigma_px;
  options.rho_floor_m = 1e-3 * flags.rho_floor_mm;
  options.alpha_floor_rad = flags.alpha_floor_deg * M_PI / 180.0;
  options.single_bar_edges = flags.single_bar_edges;
  options.calibration_floor = input->bev_uncertainty;
  if (core::Status s = options.Validate(); !s.ok()) {
    std::fprintf(stderr, "groundline extract: %s\n", s.message().c_str());
    return 2;
  }
  options.min_dark_side_contrast = flags.min_dark_contrast;
  perception::BevRemap::Options remap_options = perception::BevRemap::Options::ForLineExtraction();
  remap_options.supersampling = flags.supersampling;
  remap_options.supersampling_across = flags.supersampling_across;
  perception::BevExtent extent;
  if (!flags.bev_x_m.empty()) extent.x_m = {flags.bev_x_m[0], flags.bev_x_m[1]};
  if (!flags.bev_y_m.empty()) extent.y_m = {flags.bev_y_m[0], flags.bev_y_m[1]};
  extent.cell_m = flags.bev_cell_m;
  if (core::Status s = extent.Validate(); !s.ok()) {
    std::fprintf(stderr, "groundline extract: %s (--bev-x, --bev-y, --bev-cell)\n",
                 s.message().c_str());
    return 2;
  }
  core::Result<perception::BevGridOptions> bev_grid =
      perception::ResolveBevGrid(*input->camera, input->mount, extent);
  if (!bev_grid.ok()) {
    std::fprintf(stderr, "groundline extract: %s (mount: %s)\n", bev_grid.message().c_str(),
                 input->mount_source.c_str());
    return 1;
  }
  remap_options.grid = *bev_grid;
  const perception::BevRemap remap(*input->camera, input->mount, remap_options);
  const perception::LineExtractor extractor(remap, options);
  const perception::BevGrid& grid = remap.grid();
  const cv::Mat& mask = extractor.search_mask();
  cv::Mat unseen;
  cv::compare(remap.valid_mask(), 0, unseen, cv::CMP_EQ);
  const perception::FootprintPredicate footprint = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d c = grid.CellOfFloorPoint(p);
    const int col = static_cast<int>(std::lround(c.x())),
              row = static_cast<int>(std::lround(c.y()));
    return col >= 0 && row >= 0 && col < mask.cols && row < mask.rows &&
           mask.at<std::uint8_t>(row, col) != 0;
  };
  const bool evaluate = input->floor_map && !input->ground_truth.empty();

  // Written into a staging folder moved into --out at the end: a run that
  // fails leaves --out as it was.
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(flags.out);
  if (!staged.ok()) {
    std::fprintf(stderr, "groundline extract: %s\n", staged.message().c_str());
    return 1;
  }
  const fs::path out = staged->path();
  if (!flags.homography.empty()) {
    if (core::Status s = core::WriteFileAtomically(out / "mount.yaml",
                                                   calibration::CameraMountToYaml(input->mount));
        !s.ok()) {
      std::fprintf(stderr, "groundline extract: %s\n", s.message().c_str());
      return 1;
    }
  }
  std::set<std::string> image_names;
  // Kept in memory and written once at the end, atomically: an interrupted
  // run leaves no lines.jsonl rather than a cut one.
  std::string jsonl;
  perception::LineEvaluation evaluation;
  std::vector<double> ms;
  std::vector<std::string> skipped;
  ProgressLine progress("[extract]");
  size_t count = input->images.size();
  if (flags.max_frames > 0) count = std::min(count, static_cast<size_t>(flags.max_frames));
  for (size_t i = 0; i < count; ++i) {
    progress.Update("images", static_cast<double>(i) / count);
    const fs::path& path = input->images[i];
    const cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    if (image.empty() || image.cols != input->camera->width_px() ||
        image.rows != input->camera->height_px()) {
      const std::string why =
          image.empty() ? "cannot be read or decoded" : "is not the camera's size";
      std::fprintf(stderr, "groundline extract: skipping %s: it %s\n", path.c_str(), why.c_str());
      skipped.push_back(path.string());
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    cv::Mat bev;
    remap.Apply(image, &bev);
    const perception::LineExtraction extraction = extractor.Extract(bev);
    const double frame_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ms.push_back(frame_ms);

    std::vector<perception::TrueLine> truths;
    std::vector<std::int64_t> missed;
    nlohmann::ordered_json missed_lines = nlohmann::ordered_json::array();
    std::vector<nlohmann::ordered_json> line_truths(extraction.lines.size());
    std::vector<std::string> line_nuisances(extraction.lines.size());
    if (evaluate) {
      const std::optional<core::SE2> pose = PoseAt(input->ground_truth, input->stamps_s[i]);
      if (pose) {
        perception::VisibleLineOptions visible;
        visible.tape_occludes_joints = flags.tape_occludes_joints;
        visible.min_evaluated_run_m = flags.min_visible_run_m;
        truths = perception::VisibleMarkingLines(*input->floor_map, *pose, footprint, visible);
        std::vector<perception::LineSegmentEstimate> estimates;
        std::vector<core::MarkingPolarity> polarities;
        for (const perception::ExtractedLine& l : extraction.lines) {
          estimates.push_back({l.line, l.covariance, l.start_m, l.end_m});
          polarities.push_back(l.kind.polarity == perception::LinePolarity::kBright
                                   ? core::MarkingPolarity::kBright
                                   : core::MarkingPolarity::kDark);
        }
        const perception::LineMatches matches =
            perception::MatchLines(estimates, truths, {}, polarities);
        std::optional<std::vector<perception::NuisanceLine>> nuisances;
        if (input->nuisance_truth) {
          nuisances = input->nuisance_truth->InView(*pose, path.filename().string());
        }
        evaluation.AddFrame(extraction.lines, truths, matches, nuisances ? &*nuisances : nullptr);
        for (size_t j = 0; j < truths.size(); ++j) {
          if (truths[j].evaluated && matches.extracted_of_truth[j] < 0) {
            missed.push_back(truths[j].marking_id);
            missed_lines.push_back(MissedTruthToJson(truths[j]));
          }
        }
        for (size_t k = 0; k < extraction.lines.size(); ++k) {
          const int j = matches.truth_of_extracted[k];
          if (j >= 0) {
            line_truths[k] = TruthToJson(extraction.lines[k], truths[j]);
          } else if (nuisances) {
            // A false line: the nuisance it lies along ("none" for none).
            const std::string along = perception::NuisanceAlong(extraction.lines[k], *nuisances);
            line_nuisances[k] = along.empty() ? "none" : along;
          }
        }
      }
    }
    nlohmann::ordered_json frame = FrameToJson(path.filename().string(), frame_ms, extraction);
    if (evaluate) {
      for (size_t k = 0; k < line_truths.size(); ++k) {
        frame["lines"][k]["truth"] = line_truths[k];
        if (!line_nuisances[k].empty()) frame["lines"][k]["false_along"] = line_nuisances[k];
      }
      frame["missed_marking_ids"] = missed;
      frame["missed"] = missed_lines;
    }
    jsonl += frame.dump();
    jsonl += '\n';
    if (flags.png_every > 0 && i % static_cast<size_t>(flags.png_every) == 0) {
      // Named after the source image; a name seen before (two folders of a
      // glob) gets the frame's index.
      std::string stem = path.stem().string();
      if (!image_names.insert(stem).second) stem += "_" + std::to_string(i);
      // Shown as the camera sees the floor: the cells it does not see (which
      // the extractor's BEV fills from their nearest seen cell) are black.
      cv::Mat shown = bev.clone();
      shown.setTo(cv::Scalar::all(0), unseen);
      core::Status written = WritePngAtomically(out / ("bev_" + stem + ".png"), shown);
      if (written.ok()) {
        written = WritePngAtomically(out / ("overlay_" + stem + ".png"),
                                     DrawOverlay(shown, grid, extraction, truths));
      }
      if (!written.ok()) {
        std::fprintf(stderr, "groundline extract: %s\n", written.message().c_str());
        return 1;
      }
    }
  }
  progress.Update("images", 1.0);
  if (core::Status s = core::WriteFileAtomically(out / "lines.jsonl", jsonl); !s.ok()) {
    std::fprintf(stderr, "groundline extract: %s\n", s.message().c_str());
    return 1;
  }

  nlohmann::ordered_json summary;
  summary["frames"] = ms.size();
  summary["skipped"] = skipped;
  summary["ms_per_frame_median"] =
      ms.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(core::Median(ms));
  summary["bev"] = {{"x_m", {grid.options().x_min_m, grid.options().x_max_m}},
                    {"y_m", {grid.options().y_min_m, grid.options().y_max_m}},
                    {"cell_m", grid.cell_m()},
                    {"rows", grid.rows()},
                    {"cols", grid.cols()}};
  summary["mount"] = MountToJson(input->mount, input->mount_source);
  if (evaluate) {
    summary["tape_occludes_joints"] = flags.tape_occludes_joints;
    summary["min_visible_run_m"] = flags.min_visible_run_m;
    const nlohmann::ordered_json overall = ErrorSummaryToJson(evaluation.overall());
    for (auto it = overall.begin(); it != overall.end(); ++it) summary[it.key()] = it.value();
    nlohmann::ordered_json by_truth, by_extracted;
    for (const auto& [kind, s] : evaluation.by_truth_kind()) by_truth[kind] = ErrorSummaryToJson(s);
    for (const auto& [kind, s] : evaluation.by_extracted_kind()) {
      by_extracted[kind] = {{"detections", s.detections},
                            {"false_detections", s.false_detections},
                            {"fp_share", s.detections > 0 ? s.FpShare() : 0.0}};
    }
    summary["by_marking_kind"] = by_truth;
    summary["by_line_kind"] = by_extracted;
    if (input->nuisance_truth) summary["by_nuisance"] = NuisanceSummaryToJson(evaluation);
  }
  if (ms.empty()) {
    std::fprintf(stderr, "groundline extract: no image readable; nothing written to %s\n",
                 flags.out.c_str());
    return 1;
  }
  if (core::Status s = core::WriteFileAtomically(out / "summary.json", summary.dump(2) + "\n");
      !s.ok()) {
    std::fprintf(stderr, "groundline extract: %s\n", s.message().c_str());
    return 1;
  }
  if (core::Status s = staged->Commit(); !s.ok()) {
    std::fprintf(stderr, "groundline extract: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("extracted %zu frames (%zu skipped), median %.2f ms/frame -> %s\n", ms.size(),
              skipped.size(), ms.empty() ? 0.0 : core::Median(ms), flags.out.c_str());
  if (evaluate) {
    const perception::LineErrorSummary& o = evaluation.overall();
    std::printf(
        "  tpr %.4f  fp_share %.4f  |rho err| median %.2f mm  |alpha err| median %.3f deg"
        "  NEES in 95%% band %.3f\n",
        o.Tpr(), o.FpShare(), 1e3 * o.MedianAbsRhoErrorM(),
        o.MedianAbsAlphaErrorRad() * 180.0 / M_PI, o.NeesInsideBandShare());
    if (input->nuisance_truth) PrintNuisanceTable(evaluation);
  }
  return 0;
}

}  // namespace

CLI::App* AddExtractCommand(CLI::App& parent, CommandRunner* run) {
  auto flags = std::make_shared<ExtractFlags>();
  CLI::App* cmd = parent.add_subcommand(
      "extract", "Floor lines, junctions and their covariances from camera images");
  cmd->footer(kExtractHelp);
  cmd->add_option("input", flags->input, "Image folder or quoted glob ('dir/*.png')");
  cmd->add_option("--dataset", flags->dataset,
                  "groundline dataset directory (camera, extrinsics, images, ground truth, map)");
  cmd->add_option("--camera", flags->camera,
                  "Intrinsics: .cameramodel, OpenCV YAML or ROS camera_info (default with "
                  "--dataset: the dataset's)");
  cmd->add_option("--extrinsics", flags->extrinsics,
                  "groundline extrinsics YAML (T_base_cam; default: the dataset's, else the "
                  "reference mount)");
  cmd->add_option("--homography", flags->homography,
                  "A ground homography YAML (Duckietown's layouts: a robot's "
                  "camera_extrinsic file, which needs --camera as its camera_info, or a "
                  "version-2 file) in place of --extrinsics: the mount is decomposed from it and "
                  "its floor frame is base_link")
      ->excludes("--extrinsics");
  cmd->add_option("--bev-x", flags->bev_x_m,
                  "BEV extent along base_link x: NEAR FAR, metres ahead (default: the camera's "
                  "floor footprint: up to 30 m around its foot point, where a pixel spans at most "
                  "3 cells)")
      ->expected(2);
  cmd->add_option("--bev-y", flags->bev_y_m,
                  "BEV extent along base_link y: RIGHT LEFT, metres (default: the footprint's)")
      ->expected(2);
  cmd->add_option("--bev-cell", flags->bev_cell_m,
                  "BEV cell side [m]. The ridge filter's scale is 3.5 cells, made for 5-10 cm "
                  "tape at 1 cm: scale the cell with the markings' width (2-3 cm for 15-20 cm "
                  "road lines)")
      ->check(CLI::Range(1e-4, 1.0))
      ->capture_default_str();
  cmd->add_option("--bev-uncertainty", flags->bev_uncertainty,
                  "The calibration's floor uncertainty (bev_uncertainty.json of calibrate "
                  "floor): the floor of the line covariances (default with --dataset: the "
                  "manifest's, if any)");
  cmd->add_option("-o,--out", flags->out, "Output directory (created)")->required();
  cmd->add_option("--png-every", flags->png_every,
                  "Write BEV + overlay PNGs every Nth frame (0: none)")
      ->capture_default_str();
  cmd->add_option("--max-frames", flags->max_frames, "Process at most this many images (0: all)")
      ->capture_default_str();
  cmd->add_option("--bev-supersampling", flags->supersampling,
                  "BEV anti-aliasing: samples per cell along the floor (base_link x), averaged "
                  "(1..4; 1: none)")
      ->check(CLI::Range(1, 4))
      ->capture_default_str();
  cmd->add_option("--bev-supersampling-across", flags->supersampling_across,
                  "BEV anti-aliasing: samples per cell across (base_link y; 0: as along). The "
                  "camera's pixels are finer across the floor than along it")
      ->check(CLI::Range(0, 4))
      ->capture_default_str();
  cmd->add_option("--min-dark-contrast", flags->min_dark_contrast,
                  "A dark line (joint) is darker than both sides by this many grey levels")
      ->capture_default_str();
  cmd->add_option("--min-sigma-px", flags->min_sigma_px,
                  "Line covariance: least pixel noise of a ridge centre [px]; the noise is "
                  "measured per line from the scatter of its centres")
      ->capture_default_str();
  cmd->add_option("--rho-floor-mm", flags->rho_floor_mm,
                  "Line covariance: standard deviation of rho errors constant along a line [mm]")
      ->capture_default_str();
  cmd->add_option("--alpha-floor-deg", flags->alpha_floor_deg,
                  "Line covariance: standard deviation of alpha errors constant along a line [deg]")
      ->capture_default_str();
  cmd->add_option(
         "--single-bar-edges", flags->single_bar_edges,
         "Report the one visible edge of a wide bar (stop bar, crosswalk stripe) as a line")
      ->capture_default_str();
  cmd->add_option("--tape-occludes-joints", flags->tape_occludes_joints,
                  "Ground truth: a joint under a tape's paint (on a dash) is not seen; it counts "
                  "only between dashes or beside the tape (false: every joint under tape counts)")
      ->capture_default_str();
  cmd->add_option("--min-visible-run-m", flags->min_visible_run_m,
                  "Ground truth: a true line counts only with one unbroken run of at least this "
                  "many metres seen 1.0-2.5 m ahead (the extractor's least line length; 0: off, "
                  "every true line in view counts)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->callback([cmd, flags, run]() {
    if (flags->input.empty() == flags->dataset.empty()) {
      throw CLI::ValidationError("give either an image folder/glob or --dataset DIR");
    }
    *run = [flags]() { return RunExtract(*flags); };
    (void)cmd;
  });
  return cmd;
}

}  // namespace groundline::tools
