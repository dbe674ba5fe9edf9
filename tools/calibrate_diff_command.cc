// `groundline calibrate diff A B`: the projection difference of two
// calibrations of one camera (calibration/projection_diff.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/projection_diff.h"
#include "groundline/core/angles.h"
#include "groundline/core/atomic_file.h"
#include "json_number.h"
#include "png_file.h"

namespace groundline::tools {
namespace {

constexpr char kDiffHelp[] =
    R"(Compares two calibrations of the same camera, the way mrcal's
mrcal-show-projection-diff does: the imager is gridded, each grid pixel is
unprojected with model A, moved into model B's camera frame and projected with
model B; the difference is how far apart the two pixels land. Two calibrations
of one lens never share their camera frame exactly (each is defined by where
its boards were), so the rotation between the frames (and the translation, at
a finite --distance) is fitted first on the pixels within --focus-radius of
the imager centre; --intrinsics-only skips the fit.

Read it as: where the difference is well under the projection uncertainty of
the two reports (`calibrate intrinsics` states it), the two calibrations
agree; a difference of several tenths of a pixel where the floor is seen means
that one of them (or the lens: a knock, a refocus, heat) changed. Unlike
mrcal, the fit is not weighted by the models' uncertainties: it uses the focus
circle, mrcal's --no-uncertainties behaviour.

Models: .cameramodel, OpenCV YAML or ROS camera_info, with the same imager size.
Prints the fitted rotation (and translation) and the median and maximum
difference inside the focus circle and over the whole imager. With --out DIR:
  diff.png    the imager coloured by the difference (0 to --max-px, viridis),
              the focus circle in white, grey where a model maps nothing
  diff.json   the figures and the grid (pixel, difference vector, length)

Exit code: 0 when it ran, 1 unreadable or mismatched models, 2 usage error.

Examples:
  groundline calibrate diff monday/camera.cameramodel friday/camera.cameramodel
  groundline calibrate diff a.cameramodel b.cameramodel --distance 2 --out diff_ab)";

constexpr char kDiffCommand[] = "groundline calibrate diff";

struct DiffFlags {
  std::string model_a, model_b, out;
  calibration::ProjectionDiffOptions options;
  double max_px = 1.0;
};

std::string FormatRange(double m) {
  char text[32];
  std::snprintf(text, sizeof text, "%g m", m);
  return text;
}

int RunDiff(const DiffFlags& flags) {
  core::Result<calibration::CameraModel> a = calibration::ReadCameraModel(flags.model_a);
  if (!a.ok()) {
    std::fprintf(stderr, "%s: %s\n", kDiffCommand, a.message().c_str());
    return 1;
  }
  core::Result<calibration::CameraModel> b = calibration::ReadCameraModel(flags.model_b);
  if (!b.ok()) {
    std::fprintf(stderr, "%s: %s\n", kDiffCommand, b.message().c_str());
    return 1;
  }
  core::Result<calibration::ProjectionDiff> diff =
      calibration::ComputeProjectionDiff(*a, *b, flags.options);
  if (!diff.ok()) {
    std::fprintf(stderr, "%s: %s and %s: %s\n", kDiffCommand, flags.model_a.c_str(),
                 flags.model_b.c_str(), diff.message().c_str());
    return 1;
  }
  const Eigen::AngleAxisd rotation(diff->R10);
  const bool at_infinity = flags.options.distance_m <= 0.0;
  std::printf(
      "%s vs %s (%s, %dx%d px), points %s\n", flags.model_a.c_str(), flags.model_b.c_str(),
      a->lens_model().c_str(), a->width_px(), a->height_px(),
      at_infinity ? "at infinity" : ("at " + FormatRange(flags.options.distance_m)).c_str());
  if (flags.options.intrinsics_only) {
    std::printf("  frames: not fitted (--intrinsics-only)\n");
  } else {
    std::printf("  frames: rotation %.4f deg about (%.3f %.3f %.3f)",
                rotation.angle() * core::kRadToDeg, rotation.axis().x(),
                rotation.axis().y(), rotation.axis().z());
    if (!at_infinity) {
      std::printf(", translation (%.1f %.1f %.1f) mm", 1e3 * diff->t10.x(), 1e3 * diff->t10.y(),
                  1e3 * diff->t10.z());
    }
    std::printf("; fitted on %d grid points within %.0f px of the centre\n", diff->fit_points,
                diff->focus_radius_px);
  }
  std::printf(
      "  difference: focus circle median %.3f px, max %.3f px; whole imager median "
      "%.3f px, max %.3f px\n",
      diff->focus_median_px, diff->focus_max_px, diff->imager_median_px, diff->imager_max_px);
  if (flags.out.empty()) return 0;

  const std::filesystem::path out(flags.out);
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    std::fprintf(stderr, "%s: cannot create %s: %s\n", kDiffCommand, out.c_str(),
                 ec.message().c_str());
    return 1;
  }
  nlohmann::ordered_json j;
  j["model_a"] = flags.model_a;
  j["model_b"] = flags.model_b;
  j["lens_model"] = a->lens_model();
  j["imager_size"] = {a->width_px(), a->height_px()};
  j["distance_m"] =
      at_infinity ? nlohmann::ordered_json() : nlohmann::ordered_json(flags.options.distance_m);
  j["intrinsics_only"] = flags.options.intrinsics_only;
  j["focus_radius_px"] = diff->focus_radius_px;
  j["fit_points"] = diff->fit_points;
  j["rotation_deg"] = rotation.angle() * core::kRadToDeg;
  j["rotation_axis"] = {rotation.axis().x(), rotation.axis().y(), rotation.axis().z()};
  j["translation_m"] = {diff->t10.x(), diff->t10.y(), diff->t10.z()};
  j["focus_median_px"] = FiniteOrNull(diff->focus_median_px);
  j["focus_max_px"] = FiniteOrNull(diff->focus_max_px);
  j["imager_median_px"] = FiniteOrNull(diff->imager_median_px);
  j["imager_max_px"] = FiniteOrNull(diff->imager_max_px);
  j["grid_size"] = {diff->grid_width, diff->grid_height};
  nlohmann::ordered_json grid = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < diff->q0.size(); ++i) {
    grid.push_back({diff->q0[i].x(), diff->q0[i].y(), FiniteOrNull(diff->difference_px[i].x()),
                    FiniteOrNull(diff->difference_px[i].y()), FiniteOrNull(diff->length_px[i])});
  }
  j["grid_columns"] = {"u_px", "v_px", "du_px", "dv_px", "length_px"};
  j["grid"] = std::move(grid);
  if (core::Status s = core::WriteFileAtomically(out / "diff.json", j.dump(1) + "\n"); !s.ok()) {
    std::fprintf(stderr, "%s: %s\n", kDiffCommand, s.message().c_str());
    return 1;
  }
  const cv::Mat picture =
      calibration::RenderProjectionDiff(*diff, a->width_px(), a->height_px(), flags.max_px);
  if (core::Status s = WritePngAtomically(out / "diff.png", picture); !s.ok()) {
    std::fprintf(stderr, "%s: %s\n", kDiffCommand, s.message().c_str());
    return 1;
  }
  std::printf("  wrote %s and %s\n", (out / "diff.png").c_str(), (out / "diff.json").c_str());
  return 0;
}

}  // namespace

void AddCalibrateDiffSubcommand(CLI::App* calibrate, CommandRunner* run) {
  auto flags = std::make_shared<DiffFlags>();
  CLI::App* cmd = calibrate->add_subcommand(
      "diff", "Projection difference of two calibrations of one camera (mrcal's method)");
  cmd->footer(kDiffHelp);
  cmd->add_option("A", flags->model_a, "First model (.cameramodel, OpenCV YAML, camera_info)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("B", flags->model_b, "Second model, same imager size")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--distance", flags->options.distance_m,
                  "Range of the compared points in m (0: infinity, a rotation-only fit)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--grid", flags->options.grid_width, "Grid points across the imager")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  cmd->add_option("--focus-radius", flags->options.focus_radius_px,
                  "Radius in px of the fit's circle at the imager centre (default min(W, H) / 6)")
      ->check(CLI::Range(1.0, 1e6));
  cmd->add_flag("--intrinsics-only", flags->options.intrinsics_only,
                "Do not fit the frames: compare the lenses with the frames taken as equal");
  cmd->add_option("--max-px", flags->max_px, "Top of diff.png's colour scale, px")
      ->check(CLI::Range(1e-3, 1e3))
      ->capture_default_str();
  cmd->add_option("-o,--out", flags->out, "Directory for diff.png and diff.json");
  cmd->callback([flags, run] { *run = [flags] { return RunDiff(*flags); }; });
}

}  // namespace groundline::tools
