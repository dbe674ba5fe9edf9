// `groundline calibrate parallels IMAGES`: the camera's pitch and roll
// checked and corrected from floor markings that are parallel in still
// images (perception/mount_parallel_check.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "commands.h"
#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/core/angles.h"
#include "groundline/core/atomic_file.h"
#include "groundline/io/frame_source.h"
#include "groundline/perception/mount_parallel_check.h"
#include "png_file.h"

namespace groundline::tools {
namespace {

constexpr char kParallelsHelp[] =
    R"(Checks the camera mount's pitch and roll on floor markings that are
parallel (or perpendicular) on the floor: tape edges, lane lines, a stop bar
across an aisle. A wrong pitch makes parallel markings converge or diverge in
the bird's-eye view (BEV); a wrong roll tilts them unequally. Each image is
mapped to the BEV under --extrinsics and its lines are extracted; the pitch
and roll that make them parallel are solved for (a robust least-squares fit,
one image or many); the images are mapped and extracted again under the
solution until it stays put. Height and yaw are kept: they do not change
angles on the floor.

Prints the angles between the lines before (under --extrinsics) and after
(measured on the new extraction, not on the fit), the solved pitch and roll
with their sigmas, and writes into --out:
  extrinsics.yaml        the solved mount (the input's height, yaw, offsets)
  parallels.json         start and solved mount, sigmas, every pair of lines
                         before and after: image, lines, parallel or
                         perpendicular, degrees off
  bev_before_NAME.png, bev_after_NAME.png
                         each image's BEV with its lines (green: paired with
                         the image's longest line, in red; grey: unpaired)

The BEV grid, the least line length and the widths of bars (markings wider
than the ridge filter, found as two facing edges) scale with the mount's
height (the reference camera, 0.58 m high and pitched 42 deg down, looks
0.6-2.4 m ahead, +-1 m, in 1 cm cells, with lines of 20 cm or more and bars
8-70 cm wide). A camera pitched much
less looks farther for its height: give it its grid with --grid (the floor
it sees well, in base_link) and the length of its shortest marking (a dash)
with --min-line-length. Bright markings are used (tape, paint); --dark adds
saw-cut joints.

Exit codes: 0 ok, 1 unreadable camera, mount or images, no image with two
lines parallel or perpendicular within the gates, or the check not
confirmed: the extraction under the solved mount did not show the lines
paired again (the files are written: look at the BEVs), 2 usage error.

Example (a camera 10 cm above a taped road, its pitch to check):
  groundline calibrate parallels road/ --camera cam.yaml --extrinsics mount.yaml \
      --grid 0.15,0.75,-0.3,0.3,0.0025 --min-line-length 0.04 --out check)";

constexpr char kParallelsCommand[] = "groundline calibrate parallels";

struct ParallelsFlags {
  std::string images;
  std::string camera;
  std::string extrinsics;
  std::string out;
  std::vector<double> grid;
  double min_line_length_m = -1.0;  // < 0: the preset's
  bool dark = false;
};

int FailParallels(const std::string& message) {
  std::fflush(stdout);
  std::fprintf(stderr, "%s: %s\n", kParallelsCommand, message.c_str());
  return 1;
}

// The BEV with the image's segments drawn: the reference red, the paired
// green, the rest grey.
cv::Mat ParallelsDrawing(const cv::Mat& bev, const calibration::ParallelImage& lines,
                const std::vector<calibration::LinePairAngle>& pairs, int image,
                const perception::BevGrid& grid) {
  cv::Mat out;
  cv::cvtColor(bev, out, cv::COLOR_GRAY2BGR);
  for (std::size_t k = 0; k < lines.segments.size(); ++k) {
    cv::Scalar colour(160, 160, 160);
    for (const calibration::LinePairAngle& p : pairs) {
      if (p.image != image) continue;
      if (p.reference == static_cast<int>(k)) colour = cv::Scalar(0, 0, 255);
      if (p.other == static_cast<int>(k)) colour = cv::Scalar(0, 200, 0);
    }
    const Eigen::Vector2d a = grid.CellOfFloorPoint(lines.segments[k].start_m);
    const Eigen::Vector2d b = grid.CellOfFloorPoint(lines.segments[k].end_m);
    cv::line(out, cv::Point2d(a.x(), a.y()), cv::Point2d(b.x(), b.y()), colour, 1, cv::LINE_AA);
  }
  return out;
}

nlohmann::ordered_json ParallelPairsJson(const std::vector<calibration::LinePairAngle>& pairs,
                                 const std::vector<calibration::ParallelImage>& images) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const calibration::LinePairAngle& p : pairs) {
    j.push_back({{"image", images[p.image].name},
                 {"reference", p.reference},
                 {"other", p.other},
                 {"relation", p.perpendicular ? "perpendicular" : "parallel"},
                 {"off_deg", p.off_deg}});
  }
  return j;
}

nlohmann::ordered_json ParallelsMountJson(const calibration::CameraMount& m) {
  return {{"height_m", m.height_m},
          {"pitch_deg", m.pitch_rad * core::kRadToDeg},
          {"roll_deg", m.roll_rad * core::kRadToDeg},
          {"yaw_deg", m.yaw_rad * core::kRadToDeg}};
}

int RunParallels(const ParallelsFlags& flags) {
  namespace fs = std::filesystem;
  core::Result<calibration::CameraModel> camera = calibration::ReadCameraModel(flags.camera);
  if (!camera.ok()) return FailParallels(camera.message());
  calibration::CameraMount start;
  if (!flags.extrinsics.empty()) {
    core::Result<calibration::CameraMount> mount =
        calibration::ReadCameraMountYaml(flags.extrinsics);
    if (!mount.ok()) return FailParallels(mount.message());
    start = *mount;
  }
  perception::MountParallelCheckOptions options =
      perception::MountParallelCheckOptions::ForHeight(start.height_m);
  if (!flags.grid.empty()) {
    options.bev.grid = {flags.grid[0], flags.grid[1], flags.grid[2], flags.grid[3], flags.grid[4]};
  }
  if (flags.min_line_length_m >= 0.0) options.extractor.min_line_length_m = flags.min_line_length_m;
  options.extractor.dark = flags.dark;
  if (core::Status s = options.Validate(); !s.ok()) return FailParallels(s.message());

  std::vector<perception::NamedImage> images;
  for (const std::string& path : io::ListImageFiles(flags.images)) {
    cv::Mat grey = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) {
      std::fprintf(stderr, "%s: %s: not a readable image, skipped\n", kParallelsCommand,
                   path.c_str());
      continue;
    }
    images.push_back({fs::path(path).stem().string(), std::move(grey)});
  }
  if (images.empty()) return FailParallels(flags.images + ": no readable image");
  std::printf("%zu images; start mount: pitch %.3f deg, roll %.3f deg, height %.3f m\n",
              images.size(), start.pitch_rad * core::kRadToDeg, start.roll_rad * core::kRadToDeg,
              start.height_m);

  const core::Result<perception::MountParallelCheck> check =
      perception::CheckMountByParallels(images, *camera, start, options);
  if (!check.ok()) {
    return FailParallels(check.message() + " (the BEV grid: " +
                         std::to_string(options.bev.grid.x_min_m) + " to " +
                         std::to_string(options.bev.grid.x_max_m) + " m ahead; see --grid)");
  }
  const calibration::MountFromParallels& solution = check->solution;
  const double pitch_sigma_deg = std::sqrt(solution.covariance(0, 0)) * core::kRadToDeg;
  const double roll_sigma_deg = std::sqrt(solution.covariance(1, 1)) * core::kRadToDeg;
  std::printf("lines off parallel: before max %.2f deg, median %.2f deg (%zu pairs); after max "
              "%.2f deg, median %.2f deg (%zu pairs)\n",
              calibration::MaxOffDeg(check->measured_before),
              calibration::MedianOffDeg(check->measured_before), check->measured_before.size(),
              calibration::MaxOffDeg(check->measured_after),
              calibration::MedianOffDeg(check->measured_after), check->measured_after.size());
  std::printf("solved: pitch %.3f +- %.3f deg (%+.3f), roll %.3f +- %.3f deg (%+.3f); %d "
              "extraction rounds\n",
              solution.mount.pitch_rad * core::kRadToDeg, pitch_sigma_deg,
              (solution.mount.pitch_rad - start.pitch_rad) * core::kRadToDeg,
              solution.mount.roll_rad * core::kRadToDeg, roll_sigma_deg,
              (solution.mount.roll_rad - start.roll_rad) * core::kRadToDeg,
              check->extraction_rounds);

  std::error_code ec;
  fs::create_directories(flags.out, ec);
  if (ec) return FailParallels(flags.out + ": cannot create the directory: " + ec.message());
  const fs::path out(flags.out);
  nlohmann::ordered_json j;
  j["images"] = images.size();
  j["start"] = ParallelsMountJson(start);
  j["solved"] = ParallelsMountJson(solution.mount);
  j["pitch_sigma_deg"] = pitch_sigma_deg;
  j["roll_sigma_deg"] = roll_sigma_deg;
  j["extraction_rounds"] = check->extraction_rounds;
  j["settled"] = check->settled;
  j["measured_under"] = ParallelsMountJson(check->measured_mount);
  j["before_max_off_deg"] = calibration::MaxOffDeg(check->measured_before);
  j["after_max_off_deg"] = calibration::MaxOffDeg(check->measured_after);
  j["before"] = ParallelPairsJson(check->measured_before, check->lines_before);
  j["after"] = ParallelPairsJson(check->measured_after, check->lines_after);
  std::vector<core::Status> written = {
      calibration::WriteCameraMountYaml(solution.mount, out / "extrinsics.yaml"),
      core::WriteFileAtomically(out / "parallels.json", j.dump(1) + "\n")};
  const perception::BevGrid grid(options.bev.grid);
  for (std::size_t i = 0; i < images.size(); ++i) {
    written.push_back(WritePngAtomically(
        out / ("bev_before_" + images[i].name + ".png"),
        ParallelsDrawing(check->bev_before[i], check->lines_before[i], check->measured_before,
                static_cast<int>(i), grid)));
    written.push_back(WritePngAtomically(
        out / ("bev_after_" + images[i].name + ".png"),
        ParallelsDrawing(check->bev_after[i], check->lines_after[i], check->measured_after,
                static_cast<int>(i), grid)));
  }
  for (const core::Status& s : written) {
    if (!s.ok()) return FailParallels(s.message());
  }
  std::printf("wrote %s, %s and the BEVs before and after\n", (out / "extrinsics.yaml").c_str(),
              (out / "parallels.json").c_str());
  if (!check->settled || check->measured_after.empty()) {
    return FailParallels(
        "not confirmed: the extraction under the solved mount did not show the lines paired "
        "again (the after figures are under pitch " +
        std::to_string(check->measured_mount.pitch_rad * core::kRadToDeg) +
        " deg; see the BEVs: a dashed line may need a shorter --min-line-length, or give "
        "more images)");
  }
  return 0;
}

}  // namespace

void AddCalibrateParallelsSubcommand(CLI::App* calibrate, CommandRunner* run) {
  auto flags = std::make_shared<ParallelsFlags>();
  CLI::App* cmd = calibrate->add_subcommand(
      "parallels", "The mount's pitch and roll checked on parallel floor markings in images");
  cmd->footer(kParallelsHelp);
  cmd->add_option("IMAGES", flags->images, "Image folder or quoted glob ('dir/*.png')")
      ->required();
  cmd->add_option("--camera", flags->camera,
                  "Intrinsics: .cameramodel, OpenCV YAML or ROS camera_info")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--extrinsics", flags->extrinsics,
                  "The mount to check: groundline extrinsics YAML (default: the reference mount)")
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", flags->out, "Output directory (created)")->required();
  cmd->add_option("--grid", flags->grid,
                  "BEV grid X_MIN X_MAX Y_MIN Y_MAX CELL in metres (base_link; default: scaled "
                  "with the mount's height)")
      ->expected(5)
      ->delimiter(',');
  cmd->add_option("--min-line-length", flags->min_line_length_m,
                  "Least line length, metres (default: 0.2 m scaled with the mount's height)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--dark", flags->dark, "Also use dark markings (saw-cut joints)");
  cmd->callback([flags, run] { *run = [flags] { return RunParallels(*flags); }; });
}

}  // namespace groundline::tools
