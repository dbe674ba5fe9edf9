// `groundline calibrate`: commissioning calibrations. This file holds the
// parent command and `calibrate intrinsics`; other calibrations add their
// subcommand to the parent AddCalibrateCommand returns.
#include <algorithm>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "calib_targets_file.h"
#include "calibrate_intrinsics.h"
#include "commands.h"
#include "groundline/calibration/board_detection.h"
#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/calibration_report.h"
#include "groundline/calibration/intrinsic_calibration.h"
#include "groundline/core/atomic_file.h"
#include "groundline/io/frame_source.h"
#include "live_session.h"
#include "progress.h"

namespace groundline::tools {
namespace {

constexpr char kIntrinsicsHelp[] =
    R"(Calibrates a camera's intrinsics from images of a printed board
(`groundline targets`), solving with mrcal (mrcal_optimize) from an OpenCV seed.

--images is a directory (every .png .jpg .jpeg .bmp .pgm .tif in it) or a glob
on file names ("views/cam0_*.png"). All images must have the same size. Images
where the board is not found are listed in the report and skipped.
Take 20-40 views: the board near every corner and edge of the image, tilted
30-45 degrees in different directions, at the working distance, sharp.

Outputs in --out:
  camera.cameramodel   mrcal model (mrcal's tools read it: mrcal-show-distortion-off-pinhole ...)
  camera_opencv.yaml   OpenCV calibration file     camera_info.yaml  ROS camera_info
  report.html          PASS/FAIL, residual plots, coverage heatmap, per-image table
  report.json          the same figures             corners.vnl      the detected corners
                                                    (mrcal-calibrate-cameras --corners-cache)
Residuals are r = projected - observed in pixels; RMS is per point,
sqrt(mean |r|^2) over the corners mrcal kept. PASS needs, by default: at
least 20 views, RMS <= 0.5 px, worst |r| <= 2 px, at least 10 corners in each
image quadrant, at least 5 corners in each corner and edge zone of the
image's outer ring (10 % deep), a board tilted >= 20 deg about each axis in
some view, and a projection uncertainty (1 sigma, mrcal's method) <= 0.25 px
at 2 m over the floor part of the image. Every limit is a key of
`intrinsics_report:` in --config (docs/calibration.md). A FAIL says what to
capture next. The report states the projection uncertainty at 1, 2 and 4 m
in px and mm, and the .cameramodel carries mrcal's optimization_inputs
(mrcal-show-projection-uncertainty reads it).

Live (--live URI instead of --images): frames from a camera, the board found
in each, a frame kept only when it adds coverage (new image area, tilt or
distance; blurred frames and near-duplicates dropped). After each kept view it
prints what is still missing, e.g.
  7 of 12 views; image regions covered 7 of 9
  still missing: hold the board in the image's top-left (1 of 10 corners)
  still missing: tilt the board about its vertical axis: left or right edge 30-45 deg away
It stops when nothing is missing (--min-views views, every one of the 3 x 3
image regions with 10 corners, tilts >= 20 deg about both axes, distances
spanning x1.3), at --max-views, after --duration seconds, or on Ctrl-C, then
solves and reports exactly as with --images; what the guidance still missed
is a FAIL reason of the report. URIs: v4l2:/dev/video0[?width=1280
&height=800&format=GREY|YUYV|MJPG&fps=30], libcamera:0 (or a camera id),
folder:DIR or a glob (recorded frames). --save-frames DIR keeps the views as
PNG, so that --images DIR reruns the session.

Exit code: 0 PASS, 1 FAIL or unusable data (files are still written when the
solve ran), 2 usage error.

Example:
  groundline calibrate intrinsics --images views/ --target aprilgrid_7x5_38mm_a3 --out cam0_intrinsics
  groundline calibrate intrinsics --images 'left*.jpg' --target opencv_chessboard_9x6_25mm \
      --model LENSMODEL_OPENCV5 --out left
  groundline calibrate intrinsics --live v4l2:/dev/video0 --target aprilgrid_7x5_38mm_a3 \
      --out cam0 --save-frames cam0/frames)";

constexpr char kName[] = "groundline calibrate intrinsics";

int RunIntrinsicsFolder(const IntrinsicsFlags& flags) {
  using namespace calibration;
  IntrinsicsSetup setup;
  if (const int code = PrepareIntrinsics(flags, &setup); code != 0) return code;
  const std::vector<std::string> images = io::ListImageFiles(flags.images);
  if (images.empty()) {
    std::fprintf(stderr, "%s: --images: no image file matches '%s'\n", kName, flags.images.c_str());
    return 2;
  }
  const BoardDetectionOptions detection;
  std::vector<CalibrationView> views;
  std::vector<RejectedImage> rejected;
  cv::Size size;
  ProgressLine progress("[calibrate]");
  for (std::size_t i = 0; i < images.size(); ++i) {
    progress.Update("detecting", static_cast<double>(i) / images.size());
    const std::string name = std::filesystem::path(images[i]).filename().string();
    const cv::Mat image = cv::imread(images[i], cv::IMREAD_GRAYSCALE);
    if (image.empty()) {
      rejected.push_back({name, "cannot be read as an image"});
      continue;
    }
    if (size.area() == 0) size = image.size();
    if (image.size() != size) {
      rejected.push_back({name, "size " + std::to_string(image.cols) + "x" +
                                    std::to_string(image.rows) +
                                    " differs from the first image's"});
      continue;
    }
    core::Result<BoardObservation> obs = DetectBoard(image, setup.target, setup.grid, detection);
    if (!obs.ok()) {
      rejected.push_back({name, obs.message()});
      continue;
    }
    views.push_back({name, std::move(obs).value()});
  }
  progress.Update("detecting", 1.0);
  std::fprintf(stderr, "%s: board found in %zu of %zu images\n", kName, views.size(),
               images.size());
  for (const RejectedImage& r : rejected) {
    std::fprintf(stderr, "  skipped %s: %s\n", r.name.c_str(), r.reason.c_str());
  }
  return SolveAndReportIntrinsics(flags, setup, views, std::move(rejected), size);
}

}  // namespace

int PrepareIntrinsics(const IntrinsicsFlags& flags, IntrinsicsSetup* setup) {
  using namespace calibration;
  const std::string file =
      flags.targets_file.empty() ? DefaultCalibTargetsFile() : flags.targets_file;
  core::Result<std::vector<CalibTarget>> targets = ReadCalibTargets(file);
  if (!targets.ok()) {
    std::fprintf(stderr, "%s: %s\n", kName, targets.message().c_str());
    return 1;
  }
  core::Result<CalibTarget> target = FindCalibTarget(*targets, flags.target);
  if (!target.ok() || !target->IsBoard()) {
    std::fprintf(stderr, "%s: --target: %s\n", kName,
                 target.ok() ? (flags.target + " is a floor tag set, not a board").c_str()
                             : target.message().c_str());
    return 2;
  }
  IntrinsicCalibrationOptions& options = setup->options;
  options.lens_model = flags.model;
  options.optimize_board_warp = !flags.no_board_warp;
  options.outlier_rejection = !flags.no_outlier_rejection;
  if (core::Status s = options.Validate(); !s.ok()) {
    std::fprintf(stderr, "%s: --model: %s\n", kName, s.message().c_str());
    return 2;
  }
  if (!flags.config.empty()) {
    core::Result<ReportThresholds> read = ReadReportThresholds(flags.config);
    if (!read.ok()) {
      std::fprintf(stderr, "%s: --config: %s\n", kName, read.message().c_str());
      return 2;
    }
    setup->thresholds = *read;
  }
  setup->target = *target;
  setup->grid = MakeBoardGrid(*target);
  return 0;
}

int SolveAndReportIntrinsics(const IntrinsicsFlags& flags, const IntrinsicsSetup& setup,
                             const std::vector<calibration::CalibrationView>& views,
                             std::vector<calibration::RejectedImage> rejected, cv::Size size,
                             std::vector<std::string> live_missing) {
  using namespace calibration;
  ProgressLine progress("[calibrate]");
  progress.Update("solving", 0.0);
  core::Result<IntrinsicCalibration> cal =
      CalibrateIntrinsics(views, setup.grid, size.width, size.height, setup.options);
  if (!cal.ok()) {
    std::fprintf(stderr, "%s: %s\n", kName, cal.message().c_str());
    return 1;
  }
  progress.Update("solving", 1.0);
  const CalibrationReport report = BuildCalibrationReport(
      *cal, setup.target.name, std::move(rejected), setup.thresholds, std::move(live_missing));
  // The model, its exports and the report appear together or not at all (a
  // staging folder moved into --out; frames a live session saved there are kept).
  const std::filesystem::path out(flags.out_dir);
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(out);
  if (!staged.ok()) {
    std::fprintf(stderr, "%s: %s\n", kName, staged.message().c_str());
    return 1;
  }
  core::Status written = WriteCalibrationOutputs(staged->path(), report, *cal);
  if (written.ok()) {
    written = core::WriteFileAtomically(staged->path() / "corners.vnl",
                                        MrcalCornersVnl(views, setup.grid));
  }
  if (written.ok()) written = staged->Commit();
  if (!written.ok()) {
    std::fprintf(stderr, "%s: %s\n", kName, written.message().c_str());
    return 1;
  }
  const std::vector<double>& q = cal->camera.intrinsics();
  std::printf(
      "%s: %s, %zu views, fx %.2f fy %.2f cx %.2f cy %.2f px; RMS %.3f px, worst %.3f px, "
      "%d of %d corners rejected as outliers -> %s\n",
      report.pass ? "PASS" : "FAIL", cal->camera.lens_model().c_str(), views.size(), q[0], q[1],
      q[2], q[3], cal->summary.rms_px, cal->summary.worst_px, cal->summary.outliers,
      cal->summary.points, (out / "report.html").c_str());
  for (const UncertaintyFigure& f : report.uncertainty) {
    if (&f == &report.uncertainty.back()) break;  // the last repeats the judged range
    std::printf("  projection uncertainty at %.0f m: worst %.3f px (%.2f mm face on), 1 sigma%s\n",
                f.range_m, f.worst_px, f.worst_mm,
                f.cells_not_computable > 0 ? "; not computable in part of the image" : "");
  }
  for (const std::string& f : report.failures) std::printf("  failed: %s\n", f.c_str());
  for (const std::string& a : report.advice) std::printf("  to do: %s\n", a.c_str());
  return report.pass ? 0 : 1;
}

CLI::App* AddCalibrateCommand(CLI::App& parent, CommandRunner* run) {
  CLI::App* calibrate = parent.add_subcommand(
      "calibrate",
      "Camera intrinsics, floor mount, comparisons, self-calibration, parallel lines");
  calibrate->require_subcommand(1);
  calibrate->footer(
      "Run 'groundline calibrate <calibration> --help' for one calibration.\n"
      "Print the targets first with 'groundline targets' (docs/calibration.md).");

  CLI::App* cmd = calibrate->add_subcommand(
      "intrinsics", "Camera intrinsics (mrcal .cameramodel + OpenCV/ROS files + report)");
  cmd->footer(kIntrinsicsHelp);
  auto flags = std::make_shared<IntrinsicsFlags>();
  CLI::Option* images =
      cmd->add_option("--images", flags->images, "Directory of images or a glob on file names");
  CLI::Option* live = cmd->add_option(
      "--live", flags->live,
      "Live: a frame source URI (v4l2:/dev/video0, libcamera:0, folder:DIR); guides the "
      "technician and keeps the views that add coverage");
  images->excludes(live);
  live->excludes(images);
  cmd->add_option("--target", flags->target, "Board name from the targets file")->required();
  cmd->add_option("--model", flags->model,
                  "mrcal lens model: LENSMODEL_OPENCV8, OPENCV5, OPENCV4, OPENCV12 or PINHOLE")
      ->capture_default_str();
  cmd->add_option("--out", flags->out_dir, "Output directory (created)")->required();
  cmd->add_option("--config", flags->config,
                  "YAML with an 'intrinsics_report:' mapping of PASS/FAIL thresholds");
  cmd->add_option("--targets-file", flags->targets_file,
                  "Target definitions (default: ./calib_targets/targets.yaml, else the source "
                  "tree's)");
  cmd->add_flag("--no-board-warp", flags->no_board_warp,
                "Assume the board perfectly flat (default: solve mrcal's board flex)");
  cmd->add_flag("--no-outlier-rejection", flags->no_outlier_rejection,
                "Keep every corner (default: mrcal rejects outliers)");
  cmd->add_option("--min-views", flags->min_views,
                  "Live: views to keep before the coverage can be complete (0: the report's "
                  "min_views)")
      ->capture_default_str();
  cmd->add_option("--max-views", flags->max_views,
                  "Live: stop after this many kept views (0: no limit)")
      ->capture_default_str();
  AddLiveCaptureOptions(cmd, &flags->duration_s, &flags->timeout_s, &flags->save_frames,
                        "write the kept frames into this directory (rerun them with --images)");
  cmd->callback([run, flags, images, live]() {
    if (images->count() == 0 && live->count() == 0) {
      throw CLI::RequiredError("--images or --live");
    }
    *run = [flags]() {
      return flags->live.empty() ? RunIntrinsicsFolder(*flags) : RunIntrinsicsLive(*flags);
    };
  });
  return calibrate;
}

}  // namespace groundline::tools
