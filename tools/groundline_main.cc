// The `groundline` executable: one binary, one subcommand per user task.
#include <cstdio>
#include <exception>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "commands.h"
#include "groundline/version.h"

int main(int argc, char** argv) {
  CLI::App app{
      "groundline: centimetre localization for warehouse AGVs from floor markings,\n"
      "wheel odometry and a planar LiDAR.\n\n"
      "Run 'groundline <command> --help' for the flags of one command."};
  app.set_version_flag("--version", std::string("groundline ") + GROUNDLINE_VERSION);
  app.require_subcommand(1);
  app.fallthrough();

  groundline::tools::CommandRunner run;
  groundline::tools::AddLocalizeCommand(app, &run);
  groundline::tools::AddServeCommand(app, &run);
  groundline::tools::AddSimCommand(app, &run);
  groundline::tools::AddConvertCommand(app, &run);
  groundline::tools::AddEvalCommand(app, &run);
  groundline::tools::AddDatasetCommand(app, &run);
  groundline::tools::AddSimCommissioningCommand(app, &run);
  groundline::tools::AddTargetsCommand(app, &run);
  CLI::App* calibrate = groundline::tools::AddCalibrateCommand(app, &run);
  groundline::tools::AddCalibrateFloorSubcommand(calibrate, &run);
  groundline::tools::AddCalibrateDiffSubcommand(calibrate, &run);
  groundline::tools::AddCalibrateBevUncertaintySubcommand(calibrate, &run);
  groundline::tools::AddCalibrateHistorySubcommand(calibrate, &run);
  groundline::tools::AddCalibrateParallelsSubcommand(calibrate, &run);
  groundline::tools::AddExtractCommand(app, &run);
  groundline::tools::AddReplayDdsCommand(app, &run);

  // An unknown command is named with the list (CLI11 would only say that a
  // subcommand is required).
  std::string commands;
  bool known = false;
  for (const CLI::App* sub : app.get_subcommands({})) {
    commands += (commands.empty() ? "" : ", ") + sub->get_name();
    known = known || (argc >= 2 && sub->check_name(argv[1]));
  }
  if (argc < 2) {
    std::fprintf(stderr,
                 "groundline: no command given; the commands are: %s (see 'groundline --help')\n",
                 commands.c_str());
    return 2;
  }
  if (argv[1][0] != '-' && !known) {
    std::fprintf(
        stderr,
        "groundline: unknown command '%s'; the commands are: %s (see 'groundline --help')\n",
        argv[1], commands.c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every other parse error is a usage error (2).
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (!run) {
    std::fprintf(stderr, "groundline: no command chosen; the commands are: %s\n", commands.c_str());
    return 2;
  }
  try {
    return run();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
