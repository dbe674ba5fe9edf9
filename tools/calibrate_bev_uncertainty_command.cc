// `groundline calibrate bev-uncertainty`: the BEV uncertainty map
// (calibration/bev_uncertainty.h) of a mount that was not solved from tags
// (a tape measure, a drawing, a mount taken over from another vehicle), from
// the standard deviations its owner can state.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "groundline/calibration/bev_uncertainty.h"
#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/core/angles.h"
#include "groundline/core/atomic_file.h"

namespace groundline::tools {
namespace {

constexpr char kBevUncertaintyHelp[] =
    R"(Writes the bev_uncertainty.json of a camera mount that was measured rather
than solved (`calibrate floor` writes its own from the tag solve): the floor
position covariance that the stated uncertainties of the mount (and, with
--intrinsics-report, of the intrinsics) leave in each cell of the bird's-eye
view (docs/calibration.md, "The BEV uncertainty map"). Perception takes it as
the floor of its line covariances: `extract --bev-uncertainty FILE`, or the
dataset manifest's sensors.camera.bev_uncertainty_file for localize and serve.

The mount's numbers are taken as independent, each with the 1-sigma given
(0: known exactly). A tape-measured mount is typically known to 5 mm in
height and 0.5 deg in pitch; read the printed worst cell as what that costs
on the floor.

Exit code: 0 written, 1 unreadable camera, extrinsics or report, 2 usage error.

Example:
  groundline calibrate bev-uncertainty --camera cam.cameramodel --extrinsics mount.yaml \
      --sigma-height-mm 5 --sigma-pitch-deg 0.5 --sigma-roll-deg 0.3 --out bev_uncertainty.json)";

constexpr char kBevCommand[] = "groundline calibrate bev-uncertainty";

struct BevUncertaintyFlags {
  std::string camera, extrinsics, intrinsics_report, out;
  // 1-sigma of (height, pitch, roll, yaw, forward, lateral), mm and deg.
  double sigma_height_mm = 0.0, sigma_pitch_deg = 0.0, sigma_roll_deg = 0.0,
         sigma_yaw_deg = 0.0, sigma_forward_mm = 0.0, sigma_lateral_mm = 0.0;
  calibration::BevUncertaintyGridOptions grid;
};

int RunBevUncertainty(const BevUncertaintyFlags& flags) {
  const auto fail = [](const std::string& message, int code) {
    std::fprintf(stderr, "%s: %s\n", kBevCommand, message.c_str());
    return code;
  };
  if (core::Status s = flags.grid.Validate(); !s.ok()) return fail(s.message(), 2);
  core::Result<calibration::CameraModel> camera = calibration::ReadCameraModel(flags.camera);
  if (!camera.ok()) return fail(camera.message(), 1);
  core::Result<calibration::CameraMount> mount = calibration::ReadCameraMountYaml(flags.extrinsics);
  if (!mount.ok()) return fail(mount.message(), 1);
  std::optional<calibration::IntrinsicsReportSummary> intrinsics;
  if (!flags.intrinsics_report.empty()) {
    core::Result<calibration::IntrinsicsReportSummary> r =
        calibration::ReadIntrinsicsReportSummary(flags.intrinsics_report);
    if (!r.ok()) return fail(r.message(), 1);
    if (core::Status s = calibration::CheckSameCamera(*r, *camera, flags.camera); !s.ok()) {
      return fail(s.message(), 1);
    }
    intrinsics = std::move(r).value();
  }
  calibration::FloorExtrinsicsResult solution;
  solution.mount = *mount;
  const double deg = 1.0 / core::kRadToDeg;
  Eigen::Matrix<double, 6, 1> sd;
  sd << 1e-3 * flags.sigma_height_mm, deg * flags.sigma_pitch_deg, deg * flags.sigma_roll_deg,
      deg * flags.sigma_yaw_deg, 1e-3 * flags.sigma_forward_mm, 1e-3 * flags.sigma_lateral_mm;
  solution.covariance = sd.cwiseAbs2().asDiagonal();
  core::Result<calibration::BevUncertaintyMap> map = calibration::ComputeBevUncertaintyMap(
      *camera, solution, intrinsics ? &*intrinsics : nullptr, flags.grid);
  if (!map.ok()) return fail(map.message(), 1);
  if (map->WorstRmsMm() <= 0.0) {
    return fail("every sigma is 0 and there is no --intrinsics-report: the map would say the "
                "calibration is exact; give the mount's uncertainties",
                2);
  }
  if (core::Status s = core::WriteFileAtomically(flags.out, calibration::BevUncertaintyJson(*map));
      !s.ok()) {
    return fail(s.message(), 1);
  }
  std::printf("%s: %d cells of %.0f cm seen (x %.1f..%.1f m, y +-%.1f m), worst %.2f mm (1 sigma)\n",
              flags.out.c_str(), map->KnownCells(), 100.0 * map->cell_m, flags.grid.x_min_m,
              flags.grid.x_max_m, flags.grid.half_width_m, map->WorstRmsMm());
  for (const double x : {1.0, 1.5, 2.0, 2.5}) {
    const std::optional<Eigen::Matrix2d> c = map->CovarianceAt({x, 0.0});
    if (c) std::printf("  %.1f m ahead: %.2f mm\n", x, 1e3 * std::sqrt(c->trace()));
  }
  return 0;
}

}  // namespace

void AddCalibrateBevUncertaintySubcommand(CLI::App* calibrate, CommandRunner* run) {
  auto flags = std::make_shared<BevUncertaintyFlags>();
  CLI::App* cmd = calibrate->add_subcommand(
      "bev-uncertainty", "The BEV uncertainty map of a measured mount (for perception)");
  cmd->footer(kBevUncertaintyHelp);
  cmd->add_option("--camera", flags->camera,
                  "Intrinsics: .cameramodel, OpenCV YAML or ROS camera_info")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--extrinsics", flags->extrinsics, "The mount (groundline extrinsics YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--intrinsics-report", flags->intrinsics_report,
                  "report.json of calibrate intrinsics: adds the intrinsics' uncertainty");
  const auto sigma = [cmd](const char* name, double* value, const char* what) {
    cmd->add_option(name, *value, what)->check(CLI::Range(0.0, 1000.0))->capture_default_str();
  };
  sigma("--sigma-height-mm", &flags->sigma_height_mm, "1-sigma of the height, mm");
  sigma("--sigma-pitch-deg", &flags->sigma_pitch_deg, "1-sigma of the pitch, deg");
  sigma("--sigma-roll-deg", &flags->sigma_roll_deg, "1-sigma of the roll, deg");
  sigma("--sigma-yaw-deg", &flags->sigma_yaw_deg, "1-sigma of the yaw, deg");
  sigma("--sigma-forward-mm", &flags->sigma_forward_mm, "1-sigma of the forward offset, mm");
  sigma("--sigma-lateral-mm", &flags->sigma_lateral_mm, "1-sigma of the lateral offset, mm");
  cmd->add_option("--cell", flags->grid.cell_m, "Cell size of the map, m")->capture_default_str();
  cmd->add_option("--ahead", flags->grid.x_max_m, "The map covers 0 to this far ahead, m")
      ->capture_default_str();
  cmd->add_option("--half-width", flags->grid.half_width_m, "and this far to each side, m")
      ->capture_default_str();
  cmd->add_option("-o,--out", flags->out, "The bev_uncertainty.json to write")->required();
  cmd->callback([flags, run] { *run = [flags] { return RunBevUncertainty(*flags); }; });
}

}  // namespace groundline::tools
