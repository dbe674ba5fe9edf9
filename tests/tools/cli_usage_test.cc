// The executable's contract with its user, for every subcommand: --help
// prints that command's help and exits 0, a usage error (unknown flag,
// missing or contradictory arguments, bad values) exits 2, a data error
// (input that cannot be read or used) exits 1; `groundline --help` lists one
// line per subcommand; an unknown command exits 2 naming the commands.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::Quoted;
using testing::RunGroundline;

const std::vector<std::string> kCommands = {"localize",
                                            "serve",
                                            "sim",
                                            "convert",
                                            "convert carmen",
                                            "eval",
                                            "dataset",
                                            "dataset check",
                                            "sim-commissioning",
                                            "targets",
                                            "calibrate",
                                            "calibrate intrinsics",
                                            "calibrate floor",
                                            "calibrate history",
                                            "calibrate parallels",
                                            "extract",
                                            "replay-dds"};

TEST(CliUsage, EveryCommandHasItsOwnHelpAndUsageErrorsExit2) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "51 process starts of the instrumented CLI (0.9 s each) for flag parsing that "
                    "reads no file; runs in the release build";
  }
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("cli_usage");
  for (const std::string& command : kCommands) {
    std::string out;
    EXPECT_EQ(RunGroundline(command + " --help", dir, &out), 0) << command << ": " << out;
    EXPECT_NE(out.find("groundline " + command + " [OPTIONS]"), std::string::npos)
        << command << ": " << out;
    EXPECT_EQ(RunGroundline(command + " --no-such-flag", dir, &out), 2) << command << ": " << out;
    EXPECT_EQ(RunGroundline(command, dir, &out), 2) << command << " without arguments: " << out;
  }
}

TEST(CliUsage, MainHelpListsOneLinePerCommand) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("cli_main_help");
  std::string out;
  ASSERT_EQ(RunGroundline("--help", dir, &out), 0) << out;
  const std::size_t list = out.find("Subcommands:\n");
  ASSERT_NE(list, std::string::npos) << out;
  std::istringstream lines(out.substr(list + 13));
  std::string line;
  std::vector<std::string> names;
  while (std::getline(lines, line) && !line.empty()) {
    ASSERT_EQ(line.rfind("  ", 0), 0u) << "a continuation line in the list: '" << line << "'";
    ASSERT_NE(line[2], ' ') << "a continuation line in the list: '" << line << "'";
    EXPECT_LE(line.size(), 110u) << line;
    names.push_back(line.substr(2, line.find(' ', 2) - 2));
  }
  EXPECT_EQ(names, (std::vector<std::string>{"localize", "serve", "sim", "convert", "eval",
                                             "dataset", "sim-commissioning", "targets", "calibrate",
                                             "extract", "replay-dds"}));
}

TEST(CliUsage, UnknownCommandExits2WithTheList) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("cli_unknown");
  std::string out;
  EXPECT_EQ(RunGroundline("locallize --dataset x", dir, &out), 2) << out;
  EXPECT_NE(out.find("unknown command 'locallize'; the commands are: localize, serve, sim"),
            std::string::npos)
      << out;
  EXPECT_EQ(RunGroundline("", dir, &out), 2) << out;
  EXPECT_NE(out.find("the commands are: localize"), std::string::npos) << out;
}

TEST(CliUsage, ContradictoryArgumentsExit2AndBadDataExits1) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("cli_exit_codes");
  const std::filesystem::path empty = dir / "empty";
  std::filesystem::create_directories(empty);
  std::ofstream(dir / "garbage.tum") << "this is not a trajectory\n";
  std::ofstream(dir / "garbage.clf") << "FLASER 3 1 2\n";
  std::string out;
  // Usage: contradictory or out-of-range arguments.
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(empty) +
                              " --mode odometry --relocalize --out " + Quoted(dir / "r"),
                          dir, &out),
            2)
      << out;
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(empty) + " --initial-pose 1 2 inf --out " +
                              Quoted(dir / "r"),
                          dir, &out),
            2)
      << out;
  EXPECT_EQ(RunGroundline("sim --zone Q --out " + Quoted(dir / "s"), dir, &out), 2) << out;
  EXPECT_EQ(RunGroundline("eval", dir, &out), 2) << out;
  EXPECT_EQ(RunGroundline("extract " + Quoted(empty) + " --dataset " + Quoted(empty) + " --out " +
                              Quoted(dir / "e"),
                          dir, &out),
            2)
      << out;
  // Data: input that exists but cannot be used.
  EXPECT_EQ(RunGroundline("dataset check " + Quoted(empty), dir, &out), 1) << out;
  EXPECT_EQ(RunGroundline("localize --dataset " + Quoted(empty) + " --out " + Quoted(dir / "r"),
                          dir, &out),
            1)
      << out;
  EXPECT_EQ(RunGroundline("eval --est " + Quoted(dir / "garbage.tum") + " --ref " +
                              Quoted(dir / "garbage.tum"),
                          dir, &out),
            1)
      << out;
  EXPECT_EQ(RunGroundline(
                "convert carmen " + Quoted(dir / "garbage.clf") + " --out " + Quoted(dir / "o.tum"),
                dir, &out),
            1)
      << out;
  EXPECT_EQ(RunGroundline("extract " + Quoted(empty) + " --out " + Quoted(dir / "e"), dir, &out), 1)
      << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "r"));
  EXPECT_FALSE(std::filesystem::exists(dir / "e"));
}

}  // namespace
}  // namespace groundline
