// `groundline dataset check DIR`: reads a dataset with every check of
// core::ReadDataset and prints what it holds.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "groundline/core/dataset.h"
#include "groundline/core/dataset_summary.h"

namespace groundline::tools {
namespace {

struct CheckFlags {
  std::string dir;
  bool skip_scans = false;
  bool skip_image_files = false;
};

void PrintStream(const char* name, const core::StreamSummary& s, double nominal_rate_hz) {
  std::printf("  %-15s %7zu", name, s.count);
  if (s.count >= 2) std::printf("  at %8.3f Hz", s.mean_rate_hz);
  if (nominal_rate_hz > 0.0) std::printf("  (nominal %g Hz)", nominal_rate_hz);
  if (s.count > 0) {
    std::printf("  %.3f .. %.3f s", s.first_stamp_s, s.last_stamp_s);
  }
  std::printf("\n");
}

void PrintSummary(const core::Dataset& d, const CheckFlags& flags) {
  const core::DatasetManifest& m = d.manifest;
  const core::DatasetSummary s = core::SummarizeDataset(d);
  std::printf("dataset OK: %s\n", flags.dir.c_str());
  std::printf("  format          %s %d.%d\n", core::kDatasetFormatName, m.version_major,
              m.version_minor);
  std::printf("  name            %s\n", m.name.c_str());
  if (!m.description.empty()) {
    std::string description = m.description;
    for (std::size_t at = description.find('\n'); at != std::string::npos;
         at = description.find('\n', at + 1)) {
      description.insert(at + 1, 18, ' ');
    }
    std::printf("  description     %s\n", description.c_str());
  }
  std::printf("  duration        %.3f s (%.3f .. %.3f s)\n", s.duration_s, s.start_stamp_s,
              s.end_stamp_s);
  std::printf("  stream          records  mean rate\n");
  if (m.camera) PrintStream("images", s.images, m.camera->rate_hz);
  if (m.wheel_encoders) PrintStream("wheel_encoders", s.wheel_encoders, m.wheel_encoders->rate_hz);
  if (m.lidar) {
    if (flags.skip_scans) {
      std::printf("  %-15s (not read: --skip-scans)\n", "lidar_scans");
    } else {
      PrintStream("lidar_scans", s.scans, m.lidar->rate_hz);
      std::printf("  %-15s %.1f %% of beams have a return\n", "", 100.0 * s.scan_return_fraction);
    }
  }
  if (!m.files.ground_truth.empty()) {
    PrintStream("ground_truth", s.ground_truth, 0.0);
    std::printf("  travelled       %.3f m (ground truth)", s.ground_truth_distance_m);
    if (m.wheel_encoders) std::printf(", %.3f m (wheel encoders)", s.wheel_distance_m);
    std::printf("\n");
  } else {
    std::printf("  ground_truth    none\n");
  }
  if (d.floor_map) {
    std::printf("  floor map       %zu markings in frame '%s'\n", s.floor_markings,
                d.floor_map->frame.c_str());
  } else {
    std::printf("  floor map       none\n");
  }
  for (const auto& [key, value] : m.provenance) {
    std::printf("  provenance      %s: %s\n", key.c_str(), value.c_str());
  }
}

int RunCheck(const CheckFlags& flags) {
  core::DatasetReadOptions options;
  options.load_scans = !flags.skip_scans;
  options.check_image_files = !flags.skip_image_files;
  const core::Result<core::Dataset> dataset = core::ReadDataset(flags.dir, options);
  if (!dataset.ok()) {
    std::fprintf(stderr, "dataset INVALID: %s\n", dataset.message().c_str());
    return 1;
  }
  PrintSummary(*dataset, flags);
  return 0;
}

}  // namespace

CLI::App* AddDatasetCommand(CLI::App& parent, CommandRunner* run) {
  CLI::App* dataset = parent.add_subcommand(
      "dataset", "Check and summarize groundline datasets (format: docs/dataset.md)");
  dataset->footer(
      "A dataset is a directory: manifest.yaml, images/index.csv, wheel_encoders.csv,\n"
      "lidar_scans.txt, ground_truth.tum, floor_map.yaml (docs/dataset.md).");
  dataset->require_subcommand(1);

  auto flags = std::make_shared<CheckFlags>();
  CLI::App* check = dataset->add_subcommand(
      "check",
      "Validate a dataset directory and print a summary.\n"
      "Reads every file with all checks (format name and version, field ranges, NaN/inf,\n"
      "strictly increasing stamps, truncated lines, referenced files present) and prints the\n"
      "duration (s), the record count and mean rate (Hz) of each stream next to the nominal\n"
      "rate of the manifest, the distance travelled (m) by the ground truth and by the\n"
      "wheels, and the number of floor markings.\n"
      "Exit code: 0 valid, 1 invalid (the error names file:line and field), 2 usage.\n"
      "Example:\n"
      "  groundline dataset check /data/zone_a_run_01\n"
      "  groundline dataset check --skip-scans /data/zone_a_run_01");
  check->add_option("DIR", flags->dir, "dataset directory (the one holding manifest.yaml)")
      ->required();
  check->add_flag("--skip-scans", flags->skip_scans,
                  "do not parse lidar_scans.txt (still checks that it exists); default: parse");
  check->add_flag("--skip-image-files", flags->skip_image_files,
                  "do not check that every image in the index exists; default: check");
  check->callback([flags, run] { *run = [flags] { return RunCheck(*flags); }; });
  return dataset;
}

}  // namespace groundline::tools
