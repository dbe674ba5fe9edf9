// `groundline calibrate floor`: the camera mount from AprilTags on the floor.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "calibrate_floor.h"
#include "commands.h"
#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/core/atomic_file.h"
#include "live_session.h"

namespace groundline::tools {
namespace {

constexpr char kCalibrateFloorHelp[] =
    R"(Solves the camera mount (height, pitch, roll, yaw, forward and lateral offset;
docs/extrinsics.md) from tag36h11 AprilTags lying flat on the floor at surveyed
positions (the tag layout file, docs/tag_layout.md), seen in the images of
--images with the intrinsics of --camera.

Tags found by libapriltag (full resolution, refined edges) are matched to the
layout by id; their corners are fitted over all images with Ceres (Huber loss at
1 px). The covariance is scaled by the corner noise: --corner-sigma when given,
else the a posteriori residual sigma but at least 0.3 px (detector bias the
residuals do not show), plus the layout's survey_sigma_m when it has one.

Writes into --out:
  extrinsics.yaml     the mount (groundline_camera_extrinsics, metres and degrees)
  floor_report.json   values in mm and deg with 3-sigma bounds, expected BEV error
                      at 1, 2 and 4 m ahead, per-image and per-tag corner RMS,
                      PASS/FAIL with what failed and what to do
  floor_report.html   the same with the images rectified onto the floor and the
                      surveyed tag outlines drawn over them, and the BEV
                      uncertainty map drawn from above
  bev_uncertainty.json  the floor position covariance the calibration leaves
                      in each 20 cm cell 0-4 m ahead, +-2 m to the side (the
                      mount's part; with --intrinsics-report also the
                      intrinsics'); perception takes it as the floor of its
                      line covariances (the dataset manifest's
                      camera.bev_uncertainty_file, extract --bev-uncertainty)
PASS needs the BEV error at 2 m <= --max-bev-error (default 5 mm), every
image's corner RMS <= --max-rms (default 0.5 px), every tag's corner RMS
<= 1 px and tag corners in all four image quadrants; --config FILE sets these
under `floor_report:` (docs/calibration.md), the flags override it.
--intrinsics-report DIR/report.json (from `calibrate intrinsics`) folds the
intrinsics result in: one commissioning report with both verdicts, and the
exit code is 0 only when both pass. It is refused (exit 1) when the report is
for another camera than --camera: another imager size, lens model or model
fingerprint. With it the report also states the BEV error budget 1, 2 and
4 m ahead: the floor error from the mount, from the intrinsics (the report's
projection-uncertainty map carried to the floor) and from both.
Exit code 0 on PASS, 1 on FAIL or a data error (malformed layout, unreadable
image, no tags), 2 on usage errors.
Images without any layout tag are skipped with a warning; tags never seen warn.

Live (--live URI instead of --images; URIs as in 'calibrate intrinsics --help'):
frames from a camera, kept when they add a view of a layout tag that has fewer
than --frames-per-tag (default 3). After each kept frame it prints which tags
are not yet seen and which need more frames; it stops when every tag has
enough, at --max-frames, after --duration seconds or on Ctrl-C, writes the kept
frames into --save-frames (default OUT/frames, empty or new) and solves them as
--images does. From a camera the layout must be frame: base_link (vehicle
standing still); a frame: floor layout works live only from a folder whose
file names are the layout's vehicle poses.

Example (with a scene from 'groundline sim-commissioning --out scene'):
  groundline calibrate floor --images scene/images --layout scene/tag_layout.yaml \
      --camera scene/camera.cameramodel --out scene/calibration
  groundline calibrate floor --live folder:scene/images --layout scene/tag_layout.yaml \
      --camera scene/camera.cameramodel --out scene/live)";

int RunCalibrateFloor(const CalibrateFloorFlags& flags) {
  const auto fail = [](const std::string& message) {
    std::fprintf(stderr, "groundline calibrate floor: %s\n", message.c_str());
    return 1;
  };
  core::Result<calibration::TagLayout> layout = calibration::ReadTagLayout(flags.layout);
  if (!layout.ok()) return fail(layout.message());
  core::Result<calibration::CameraModel> camera = calibration::ReadCameraModel(flags.camera);
  if (!camera.ok()) return fail(camera.message());
  calibration::FloorCalibrationOptions options;
  if (!flags.config.empty()) {
    core::Result<calibration::FloorReportThresholds> t =
        calibration::ReadFloorReportThresholds(flags.config);
    if (!t.ok()) return fail(t.message());
    options.thresholds = *t;
  }
  if (flags.max_bev_given) options.thresholds.max_bev_error_2m_mm = flags.max_bev_error_2m_mm;
  if (flags.max_rms_given) options.thresholds.max_image_rms_px = flags.max_rms_px;
  options.solver.corner_sigma_px = flags.corner_sigma_px;
  if (!flags.intrinsics_report.empty()) {  // fail before a live session, not after it
    const auto read = calibration::ReadIntrinsicsReportSummary(flags.intrinsics_report);
    if (!read.ok()) return fail(read.message());
    if (core::Status same = calibration::CheckSameCamera(*read, *camera, flags.camera);
        !same.ok()) {
      return fail(same.message());
    }
  }
  if (core::Status s = options.Validate(); !s.ok()) {
    std::fprintf(stderr, "groundline calibrate floor: %s\n", s.message().c_str());
    return 2;
  }
  if (!flags.live.empty()) return RunCalibrateFloorLive(flags, *layout, *camera, options);
  return SolveAndReportFloor(flags, *layout, *camera, flags.images, options);
}

}  // namespace

int SolveAndReportFloor(const CalibrateFloorFlags& flags, const calibration::TagLayout& layout,
                        const calibration::CameraModel& camera,
                        const std::filesystem::path& image_dir,
                        const calibration::FloorCalibrationOptions& options) {
  const auto fail = [](const std::string& message) {
    std::fprintf(stderr, "groundline calibrate floor: %s\n", message.c_str());
    return 1;
  };
  std::optional<calibration::IntrinsicsReportSummary> intrinsics;
  if (!flags.intrinsics_report.empty()) {
    core::Result<calibration::IntrinsicsReportSummary> read =
        calibration::ReadIntrinsicsReportSummary(flags.intrinsics_report);
    if (!read.ok()) return fail(read.message());
    intrinsics = *read;
  }
  const calibration::IntrinsicsReportSummary* intrinsics_ptr = intrinsics ? &*intrinsics : nullptr;
  core::Result<calibration::FloorCalibration> result =
      calibration::CalibrateFloor(camera, layout, image_dir, options);
  if (!result.ok()) return fail(result.message());
  if (intrinsics) calibration::AddIntrinsicsToBev(camera, *intrinsics, &*result);
  for (const std::string& w : result->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

  // The mount and its reports appear together or not at all (a staging
  // folder moved into --out; frames a live session saved there are kept).
  const std::filesystem::path out(flags.out);
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(out);
  if (!staged.ok()) return fail(staged.message());
  const std::filesystem::path staging = staged->path();
  for (const core::Status& s :
       {calibration::WriteCameraMountYaml(result->solution.mount, staging / "extrinsics.yaml"),
        core::WriteFileAtomically(staging / "floor_report.json",
                                  calibration::FloorReportJson(*result, options, intrinsics_ptr)),
        core::WriteFileAtomically(
            staging / "floor_report.html",
            calibration::FloorReportHtml(*result, layout, camera, options, intrinsics_ptr))}) {
    if (!s.ok()) return fail(s.message());
  }
  if (!result->bev_map.covariance_m2.empty()) {
    if (core::Status s = core::WriteFileAtomically(staging / "bev_uncertainty.json",
                                                   calibration::BevUncertaintyJson(result->bev_map));
        !s.ok()) {
      return fail(s.message());
    }
  }
  if (core::Status s = staged->Commit(); !s.ok()) return fail(s.message());
  const calibration::FloorExtrinsicsResult& r = result->solution;
  const auto sd3 = [&r](int i, double scale) {
    return 3.0 * std::sqrt(r.covariance(i, i)) * scale;
  };
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  std::printf(
      "%s: %zu images, %d corners, RMS %.3f px\n"
      "  height  %8.2f mm  +- %.2f (3 sigma)\n  pitch   %8.3f deg +- %.3f\n"
      "  roll    %8.3f deg +- %.3f\n  yaw     %8.3f deg +- %.3f\n"
      "  forward %8.2f mm  +- %.2f\n  lateral %8.2f mm  +- %.2f\n"
      "  BEV error (1 sigma) at 1/2/4 m: %.2f / %.2f / %.2f mm\n%s\n",
      out.string().c_str(), result->images.size(), r.corners, r.rms_px, r.mount.height_m * 1e3,
      sd3(0, 1e3), r.mount.pitch_rad * kDeg, sd3(1, kDeg), r.mount.roll_rad * kDeg, sd3(2, kDeg),
      r.mount.yaw_rad * kDeg, sd3(3, kDeg), r.mount.forward_m * 1e3, sd3(4, 1e3),
      r.mount.lateral_m * 1e3, sd3(5, 1e3), result->bev[0].rms_mm, result->bev[1].rms_mm,
      result->bev[2].rms_mm, result->verdict.c_str());
  for (const std::string& a : result->advice) std::printf("  to do: %s\n", a.c_str());
  if (!result->bev_map.covariance_m2.empty()) {
    std::printf("  BEV uncertainty map (%s): %d cells of %.0f cm seen, worst %.2f mm -> "
                "bev_uncertainty.json\n",
                result->bev_map.includes_intrinsics ? "mount and intrinsics" : "mount only",
                result->bev_map.KnownCells(), result->bev_map.cell_m * 100.0,
                result->bev_map.WorstRmsMm());
  }
  if (intrinsics) {
    for (const calibration::BevErrorBudget& b : result->bev_budget) {
      if (!b.known) {
        std::printf("  BEV error %.0f m ahead: intrinsics part not known\n", b.distance_m);
        continue;
      }
      std::printf(
          "  BEV error %.0f m ahead (1 sigma): mount %.2f mm, intrinsics %.2f mm, both "
          "%.2f mm\n",
          b.distance_m, b.extrinsics_rms_mm, b.intrinsics_rms_mm, b.total_rms_mm);
    }
    std::printf("intrinsics (%s): %s\ncommissioning: %s\n", intrinsics->source.c_str(),
                intrinsics->pass ? "PASS" : "FAIL",
                result->pass && intrinsics->pass ? "PASS" : "FAIL");
    return result->pass && intrinsics->pass ? 0 : 1;
  }
  return result->pass ? 0 : 1;
}

void AddCalibrateFloorSubcommand(CLI::App* calibrate, CommandRunner* run) {
  auto flags = std::make_shared<CalibrateFloorFlags>();
  CLI::App* cmd = calibrate->add_subcommand(
      "floor", "Camera mount (extrinsics) from AprilTags surveyed on the floor");
  cmd->footer(kCalibrateFloorHelp);
  CLI::Option* images = cmd->add_option("--images", flags->images, "Directory of the images");
  CLI::Option* live = cmd->add_option(
      "--live", flags->live,
      "Live: a frame source URI (v4l2:/dev/video0, libcamera:0, folder:DIR); says which tags "
      "are still missing");
  images->excludes(live);
  live->excludes(images);
  cmd->add_option("--layout", flags->layout, "Tag layout file (docs/tag_layout.md)")->required();
  cmd->add_option("--camera", flags->camera,
                  "Intrinsics: .cameramodel, OpenCV YAML or ROS camera_info")
      ->required();
  cmd->add_option("-o,--out", flags->out, "Output directory")->required();
  cmd->add_option("--max-bev-error", flags->max_bev_error_2m_mm,
                  "PASS threshold on the BEV error 2 m ahead, mm")
      ->capture_default_str();
  cmd->add_option("--max-rms", flags->max_rms_px, "PASS threshold on each image's corner RMS, px")
      ->capture_default_str();
  cmd->add_option("--corner-sigma", flags->corner_sigma_px,
                  "Corner noise in px for the covariance (0: a posteriori)")
      ->capture_default_str();
  cmd->add_option("--frames-per-tag", flags->frames_per_tag,
                  "Live: kept frames each layout tag must appear in")
      ->capture_default_str();
  cmd->add_option("--max-frames", flags->max_frames,
                  "Live: stop after this many kept frames (0: no limit)")
      ->capture_default_str();
  AddLiveCaptureOptions(cmd, &flags->duration_s, &flags->timeout_s, &flags->save_frames,
                        "directory for the kept frames (default OUT/frames)");
  cmd->add_option("--config", flags->config,
                  "YAML with a 'floor_report:' mapping of PASS/FAIL thresholds");
  cmd->add_option("--intrinsics-report", flags->intrinsics_report,
                  "report.json of `calibrate intrinsics` to fold into one commissioning report");
  cmd->callback([flags, run, images, live, cmd] {
    if (images->count() == 0 && live->count() == 0) {
      throw CLI::RequiredError("--images or --live");
    }
    flags->max_bev_given = cmd->count("--max-bev-error") > 0;
    flags->max_rms_given = cmd->count("--max-rms") > 0;
    *run = [flags] { return RunCalibrateFloor(*flags); };
  });
}

}  // namespace groundline::tools
