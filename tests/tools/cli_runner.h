// Runs the `groundline` executable as a user would, for end-to-end tests.
#ifndef GROUNDLINE_TESTS_TOOLS_CLI_RUNNER_H_
#define GROUNDLINE_TESTS_TOOLS_CLI_RUNNER_H_

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "test_data.h"
#include "tools_under_test.h"

namespace groundline::testing {

// Runs `groundline <args>` (args are passed to the shell as written; quote
// paths) and returns its exit code; stdout and stderr together in *output.
// The captured output goes to <dir>/cli_output.txt.
// A JSON file; throws (failing the test) when it is missing or malformed.
inline nlohmann::json ReadJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

inline int RunGroundline(const std::string& args, const std::filesystem::path& dir,
                         std::string* output) {
  const std::filesystem::path log = dir / "cli_output.txt";
  const std::string command = std::string("'") + ::groundline::testing::GroundlineCli() + "' " +
                              args + " > '" + log.string() + "' 2>&1";
  const int status = std::system(command.c_str());
  *output = ReadText(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline std::string Quoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_TOOLS_CLI_RUNNER_H_
