// Subcommands of the `groundline` executable. Each Add*Command registers its
// flags on `parent` and, when the subcommand is chosen on the command line,
// stores in *run the function that executes it (returning the exit code:
// 0 success, 1 failure caused by the input data, 2 usage error).
//
// The commands are thin: they turn flags and config files into the Options of
// the libraries and call them.
#ifndef GROUNDLINE_TOOLS_COMMANDS_H_
#define GROUNDLINE_TOOLS_COMMANDS_H_

#include <functional>

#include <CLI/CLI.hpp>

namespace groundline::tools {

using CommandRunner = std::function<int()>;

// `groundline convert carmen`: raw-odometry trajectory of a CARMEN log.
CLI::App* AddConvertCommand(CLI::App& parent, CommandRunner* run);

// `groundline localize`: replays a dataset and writes trajectory, health and summary.
CLI::App* AddLocalizeCommand(CLI::App& parent, CommandRunner* run);
// `groundline serve`: the localizer as a long-running service (serve_command.cc).
CLI::App* AddServeCommand(CLI::App& parent, CommandRunner* run);

// `groundline sim`: a simulated warehouse run written as a dataset.
CLI::App* AddSimCommand(CLI::App& parent, CommandRunner* run);

// `groundline eval`: trajectory metrics against a reference and/or relations.
CLI::App* AddEvalCommand(CLI::App& parent, CommandRunner* run);
// `groundline dataset check DIR`: validates a dataset directory and prints a
// summary (tools/dataset_command.cc).
CLI::App* AddDatasetCommand(CLI::App& parent, CommandRunner* run);
// `groundline extract`: floor lines of images or a dataset (tools/extract_command.cc).
CLI::App* AddExtractCommand(CLI::App& parent, CommandRunner* run);

// `groundline targets`: printable calibration targets, SVG + PNG
// (tools/targets_command.cc).
CLI::App* AddTargetsCommand(CLI::App& parent, CommandRunner* run);

// `groundline calibrate`: the parent of the commissioning calibrations, with
// `calibrate intrinsics` (tools/calibrate_command.cc). Returns the parent so
// that other calibrations (`calibrate floor`) can add their subcommand to it.
CLI::App* AddCalibrateCommand(CLI::App& parent, CommandRunner* run);
// `groundline sim-commissioning`: a tag mat on the floor seen from a few vehicle
// poses, with the layout, intrinsics and true extrinsics
// (tools/sim_commissioning_command.cc).
CLI::App* AddSimCommissioningCommand(CLI::App& parent, CommandRunner* run);

// `groundline calibrate floor`: the camera mount from tags on the floor
// (tools/calibrate_floor_command.cc); hangs on the `calibrate` parent.
void AddCalibrateFloorSubcommand(CLI::App* calibrate, CommandRunner* run);

// `groundline calibrate diff A B`: the projection difference of two
// calibrations of one camera (tools/calibrate_diff_command.cc).
void AddCalibrateDiffSubcommand(CLI::App* calibrate, CommandRunner* run);

// `groundline calibrate bev-uncertainty`: the BEV uncertainty map of a
// measured mount (tools/calibrate_bev_uncertainty_command.cc).
void AddCalibrateBevUncertaintySubcommand(CLI::App* calibrate, CommandRunner* run);

// `groundline calibrate history RUN`: a recorded run's self-calibration of
// the camera mount (tools/calibrate_history_command.cc).
void AddCalibrateHistorySubcommand(CLI::App* calibrate, CommandRunner* run);

// `groundline calibrate parallels IMAGES`: the mount's pitch and roll from
// parallel floor markings in still images (tools/calibrate_parallels_command.cc).
void AddCalibrateParallelsSubcommand(CLI::App* calibrate, CommandRunner* run);

// `groundline replay-dds DATASET`: a dataset's sensor streams as ROS 2 topics
// over DDS (tools/replay_dds_command.cc).
CLI::App* AddReplayDdsCommand(CLI::App& parent, CommandRunner* run);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_COMMANDS_H_
