// Locating the shared public data (../shared/data beside the repository, or
// $GROUNDLINE_DATA_DIR), scratch directories for tests, and reading a file whole.
#ifndef GROUNDLINE_TESTS_SUPPORT_TEST_DATA_H_
#define GROUNDLINE_TESTS_SUPPORT_TEST_DATA_H_

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace groundline::testing {

// The shared data directory: $GROUNDLINE_DATA_DIR if set, else the one CMake
// recorded (../shared/data next to the source tree).
inline std::filesystem::path SharedDataDir() {
  if (const char* env = std::getenv("GROUNDLINE_DATA_DIR"); env != nullptr && *env != '\0') {
    return env;
  }
  return GROUNDLINE_SHARED_DATA_DIR;
}

// A fresh, empty directory for one test, removed and recreated on each call.
inline std::filesystem::path ScratchDir(const std::string& name) {
  std::filesystem::path base = std::filesystem::temp_directory_path();
  if (const char* env = std::getenv("GROUNDLINE_TEST_TMPDIR"); env != nullptr && *env != '\0') {
    base = env;
  }
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = base / (std::string(info ? info->test_suite_name() : "suite") + "." +
                                      (info ? info->name() : "test") + "." + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The whole content of a file, byte for byte ("" when it cannot be read).
inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace groundline::testing

// Skips the current test, with the path and the reason, when a shared data
// file or folder is absent.
#define GROUNDLINE_REQUIRE_DATA(relative_path)                                              \
  do {                                                                                      \
    const std::filesystem::path groundline_data_path_ =                                     \
        ::groundline::testing::SharedDataDir() / (relative_path);                           \
    if (!std::filesystem::exists(groundline_data_path_)) {                                  \
      GTEST_SKIP() << "shared data absent: " << groundline_data_path_                       \
                   << " (set GROUNDLINE_DATA_DIR or place ../shared/data beside the repo)"; \
    }                                                                                       \
  } while (0)

#endif  // GROUNDLINE_TESTS_SUPPORT_TEST_DATA_H_
