// The `groundline` executable: one binary, one subcommand per user task.
#include <cstdio>
#include <exception>

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
  groundline::tools::AddExtractCommand(app, &run);
  groundline::tools::AddReplayDdsCommand(app, &run);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every other parse error is a usage error (2).
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (!run) {
    std::fprintf(stderr, "groundline: no command chosen; see 'groundline --help'\n");
    return 2;
  }
  try {
    return run();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
