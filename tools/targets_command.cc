// `groundline targets`: printable calibration targets (SVG at exact scale and
// PNG at a chosen DPI) from calib_targets/targets.yaml.
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "calib_targets_file.h"
#include "commands.h"
#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/target_render.h"
#include "groundline/core/atomic_file.h"
#include "png_file.h"

namespace groundline::tools {
namespace {

struct TargetsFlags {
  std::vector<std::string> names;
  bool list = false;
  std::string out_dir = "targets";
  double dpi = 300.0;
  bool no_png = false;
  std::string targets_file;
};

constexpr char kTargetsHelp[] =
    R"(Writes printable calibration targets defined in calib_targets/targets.yaml:
for each sheet an SVG at exact scale (vector, millimetre units: print this) and
a PNG at --dpi (for viewers and printers without SVG). Boards (chessboards,
AprilGrids of tag36h11 tags) give one sheet; floor tag sets give one sheet per
tag (NAME_idNNN), each with the tag id, centre marks and corner marks.

Every sheet carries a 100 mm scale bar. Print at 100 % ("actual size", never
"fit to page"), then measure the bar with a ruler: if it is not 100 mm, the
printer scaled the sheet and the calibration would be wrong by that factor.
Glue boards flat on a rigid plate.

Examples:
  groundline targets --list
  groundline targets --target aprilgrid_7x5_38mm_a3 --out targets
  groundline targets --target floor_tags_a4_150mm --dpi 150 --out floor_tags)";

int RunTargets(const TargetsFlags& flags) {
  const std::string file =
      flags.targets_file.empty() ? DefaultCalibTargetsFile() : flags.targets_file;
  core::Result<std::vector<calibration::CalibTarget>> targets = calibration::ReadCalibTargets(file);
  if (!targets.ok()) {
    std::fprintf(stderr, "groundline targets: %s\n", targets.message().c_str());
    return 1;
  }
  if (flags.list || flags.names.empty()) {
    std::printf("targets in %s:\n", file.c_str());
    for (const calibration::CalibTarget& t : *targets) {
      const Eigen::Vector2d size = t.PatternSize_m() * 1000.0;
      std::printf("  %-32s %-16s %.0f x %.0f mm%s\n", t.name.c_str(),
                  calibration::TargetTypeName(t.type), size.x(), size.y(),
                  t.IsBoard() ? "" : (" per tag, " + std::to_string(t.count) + " sheets").c_str());
    }
    if (!flags.list) std::fprintf(stderr, "groundline targets: choose one with --target NAME\n");
    return flags.list ? 0 : 2;
  }
  // Written into a staging folder moved into --out at the end: a failed run
  // leaves --out as it was.
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(flags.out_dir);
  if (!staged.ok()) {
    std::fprintf(stderr, "groundline targets: %s\n", staged.message().c_str());
    return 1;
  }
  for (const std::string& name : flags.names) {
    core::Result<calibration::CalibTarget> target = calibration::FindCalibTarget(*targets, name);
    if (!target.ok()) {
      std::fprintf(stderr, "groundline targets: %s\n", target.message().c_str());
      return 2;
    }
    core::Result<std::vector<calibration::TargetSheet>> sheets = calibration::LayoutTarget(*target);
    if (!sheets.ok()) {
      std::fprintf(stderr, "groundline targets: %s\n", sheets.message().c_str());
      return 1;
    }
    const std::filesystem::path out = staged->path();
    for (const calibration::TargetSheet& sheet : *sheets) {
      const std::filesystem::path svg = out / (sheet.file_stem + ".svg");
      if (core::Status s = core::WriteFileAtomically(svg, calibration::SheetToSvg(sheet));
          !s.ok()) {
        std::fprintf(stderr, "groundline targets: %s\n", s.message().c_str());
        return 1;
      }
      if (!flags.no_png) {
        if (core::Status s = WritePngAtomically(out / (sheet.file_stem + ".png"),
                                                calibration::RasterizeSheet(sheet, flags.dpi));
            !s.ok()) {
          std::fprintf(stderr, "groundline targets: %s\n", s.message().c_str());
          return 1;
        }
      }
    }
    std::printf("%s: %zu sheet(s) on %s (%.0f x %.0f mm) in %s%s\n", name.c_str(), sheets->size(),
                sheets->front().paper.c_str(), sheets->front().width_mm, sheets->front().height_mm,
                flags.out_dir.c_str(),
                flags.no_png
                    ? ""
                    : (", PNG at " + std::to_string(static_cast<int>(flags.dpi)) + " dpi").c_str());
  }
  if (core::Status s = staged->Commit(); !s.ok()) {
    std::fprintf(stderr, "groundline targets: %s\n", s.message().c_str());
    return 1;
  }
  return 0;
}

}  // namespace

CLI::App* AddTargetsCommand(CLI::App& parent, CommandRunner* run) {
  CLI::App* cmd = parent.add_subcommand("targets", "Printable calibration targets (SVG + PNG)");
  cmd->footer(kTargetsHelp);
  auto flags = std::make_shared<TargetsFlags>();
  cmd->add_option("--target", flags->names, "Target name(s) from the targets file (repeatable)");
  cmd->add_flag("--list", flags->list, "List the targets defined and exit");
  cmd->add_option("--out", flags->out_dir, "Output directory (created)")->capture_default_str();
  cmd->add_option("--dpi", flags->dpi, "PNG resolution, dots per inch")
      ->capture_default_str()
      ->check(CLI::Range(10.0, 1200.0));
  cmd->add_flag("--no-png", flags->no_png, "Write the SVG only");
  cmd->add_option("--targets-file", flags->targets_file,
                  "Target definitions (default: ./calib_targets/targets.yaml, else the source "
                  "tree's)");
  cmd->callback([run, flags]() { *run = [flags]() { return RunTargets(*flags); }; });
  return cmd;
}

}  // namespace groundline::tools
