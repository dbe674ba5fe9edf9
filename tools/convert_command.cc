// `groundline convert carmen`: a CARMEN log's raw-odometry trajectory as a
// TUM or EuRoC file, for `groundline eval` and for evo.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/io/carmen.h"
#include "groundline/io/carmen_trajectory.h"

namespace groundline::tools {
namespace {

struct ConvertCarmenFlags {
  std::string log_path;
  std::string out_path;
  std::string pose = "odometry";
  int laser = 1;
  bool strict = false;
};

constexpr char kCarmenHelp[] =
    R"(Writes the raw-odometry trajectory of a CARMEN log (plain, .gz or .bz2).

One pose per laser scan of the chosen laser (FLASER/ROBOTLASER1 for --laser 1,
RLASER/ROBOTLASER2 for 2), stamped with the scan's ipc_timestamp [s], holding the
odometry pose written in that scan line (--pose odometry: T_odom_base) or the laser's
pose (--pose laser: T_odom_laser). This is the 'raw odometry' baseline of the
Kuemmerle et al. 2009 benchmark; its .relations files use the same timestamps.
The output format follows the extension: .csv is EuRoC, anything else TUM.
Malformed lines are skipped and counted (reported on stderr) unless --strict.

Example:
  groundline convert carmen ../shared/data/lidar2d/aces.clf.bz2 --out aces_odom.tum
  groundline eval --est aces_odom.tum --relations ../shared/data/lidar2d/aces.relations)";

int RunConvertCarmen(const ConvertCarmenFlags& flags) {
  io::CarmenReadOptions read_options;
  read_options.strict = flags.strict;
  core::Result<io::CarmenLog> log = io::ReadCarmenLog(flags.log_path, read_options);
  if (!log.ok()) {
    std::fprintf(stderr, "groundline convert carmen: %s\n", log.message().c_str());
    return 1;
  }
  io::CarmenTrajectoryOptions options;
  options.pose_source =
      flags.pose == "laser" ? io::CarmenPoseSource::kLaser : io::CarmenPoseSource::kOdometry;
  options.laser_id = flags.laser;
  core::Result<core::Trajectory> trajectory = io::CarmenScanTrajectory(*log, options);
  if (!trajectory.ok()) {
    std::fprintf(stderr, "groundline convert carmen: %s\n", trajectory.message().c_str());
    return 1;
  }
  if (trajectory->empty()) {
    std::fprintf(stderr,
                 "groundline convert carmen: %s has no scan of laser %d with a pose "
                 "(RAWLASER lines carry none); try --laser 2\n",
                 flags.log_path.c_str(), flags.laser);
    return 1;
  }
  const core::Status written = core::WriteTrajectory(flags.out_path, *trajectory,
                                                     core::GuessTrajectoryFormat(flags.out_path));
  if (!written.ok()) {
    std::fprintf(stderr, "groundline convert carmen: %s\n", written.message().c_str());
    return 1;
  }
  const io::CarmenReadSummary& summary = log->summary;
  std::printf("%s: %lld lines, %zu scans, %zu odometry messages -> %zu poses in %s\n",
              flags.log_path.c_str(), static_cast<long long>(summary.lines), log->scans.size(),
              log->odometry.size(), trajectory->size(), flags.out_path.c_str());
  if (summary.skipped_line_count > 0) {
    std::fprintf(stderr, "skipped %lld malformed lines; first: line %lld: %s\n",
                 static_cast<long long>(summary.skipped_line_count),
                 static_cast<long long>(summary.skipped_lines.front().line),
                 summary.skipped_lines.front().reason.c_str());
  }
  return 0;
}

}  // namespace

CLI::App* AddConvertCommand(CLI::App& parent, CommandRunner* run) {
  CLI::App* convert = parent.add_subcommand(
      "convert", "Convert real logs into groundline's formats (TUM/EuRoC trajectories)");
  convert->require_subcommand(1);
  auto flags = std::make_shared<ConvertCarmenFlags>();
  CLI::App* carmen = convert->add_subcommand("carmen", "Raw-odometry trajectory of a CARMEN log");
  carmen->footer(kCarmenHelp);
  carmen->add_option("log", flags->log_path, "CARMEN log (.clf, .clf.gz, .clf.bz2)")
      ->required()
      ->check(CLI::ExistingFile);
  carmen->add_option("-o,--out", flags->out_path, "Output trajectory (.tum, or .csv for EuRoC)")
      ->required();
  carmen->add_option("--pose", flags->pose, "Which pose of each scan line to write")
      ->check(CLI::IsMember({"odometry", "laser"}))
      ->capture_default_str();
  carmen->add_option("--laser", flags->laser, "CARMEN laser number (1 front, 2 rear)")
      ->check(CLI::Range(1, 4))
      ->capture_default_str();
  carmen->add_flag("--strict", flags->strict, "Fail on the first malformed line");
  carmen->callback([flags, run] { *run = [flags] { return RunConvertCarmen(*flags); }; });
  return convert;
}

}  // namespace groundline::tools
