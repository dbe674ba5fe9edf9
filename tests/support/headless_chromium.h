// Headless Chromium for tests of the project's HTML pages: the DOM after the
// page's scripts ran, and screenshots. The browser is Debian's `chromium`
// (scripts/setup.sh), or $GROUNDLINE_CHROMIUM; tests skip without it.
#ifndef GROUNDLINE_TESTS_SUPPORT_HEADLESS_CHROMIUM_H_
#define GROUNDLINE_TESTS_SUPPORT_HEADLESS_CHROMIUM_H_

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.h"

namespace groundline::testing {

// $GROUNDLINE_CHROMIUM if set, else the first `chromium` executable in PATH;
// empty when there is none.
inline std::filesystem::path FindChromium() {
  if (const char* env = std::getenv("GROUNDLINE_CHROMIUM"); env != nullptr && *env != '\0') {
    return ::access(env, X_OK) == 0 ? std::filesystem::path(env) : std::filesystem::path();
  }
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::filesystem::path candidate = std::filesystem::path(dir) / "chromium";
    if (!dir.empty() && ::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

// What one headless run printed; ok is false (and error says why, with the
// browser's log) when it did not exit 0 within the time-out.
struct BrowserRun {
  bool ok = false;
  std::string stdout_text;
  std::string error;
};

// Runs headless Chromium on url with the extra flags. Every run gets its own
// profile under work_dir (parallel tests would otherwise share one and hand
// their URL to each other's browser). virtual_time_ms: the page's timers and
// fetches run for that much virtual time (--virtual-time-budget) before the
// DOM is dumped or the screenshot taken; Chromium waits for pending network
// requests before advancing it, so a page that polls its server gets its
// answers even on a slow machine.
inline BrowserRun RunHeadlessChromium(const std::string& url, std::vector<std::string> flags,
                                      int virtual_time_ms, const std::filesystem::path& work_dir,
                                      const std::string& name) {
  BrowserRun run;
  const std::filesystem::path chromium = FindChromium();
  if (chromium.empty()) {
    run.error = "chromium not found";
    return run;
  }
  std::vector<std::string> argv = {chromium.string(),
                                   "--headless",
                                   "--no-sandbox",
                                   "--disable-gpu",
                                   "--disable-dev-shm-usage",
                                   "--no-first-run",
                                   "--no-default-browser-check",
                                   "--disable-extensions",
                                   "--disable-background-networking",
                                   "--hide-scrollbars",
                                   "--user-data-dir=" + (work_dir / (name + ".profile")).string(),
                                   "--virtual-time-budget=" + std::to_string(virtual_time_ms)};
  argv.insert(argv.end(), flags.begin(), flags.end());
  argv.push_back(url);
  const std::filesystem::path out = work_dir / (name + ".stdout");
  const std::filesystem::path err = work_dir / (name + ".stderr");
  ChildProcess browser(argv, out, err);
  if (!browser.started()) {
    run.error = "could not start " + chromium.string();
    return run;
  }
  // A page load takes 1-3 s on 2 busy cores; 60 s means the browser hung.
  const int code = browser.Wait(std::chrono::seconds(60));
  run.stdout_text = browser.output();
  if (code != 0) {
    run.error = chromium.string() + " on " + url +
                (code < 0 ? ": no exit after 60 s" : ": exit code " + std::to_string(code)) +
                "; its log:\n" + ReadText(err);
    return run;
  }
  run.ok = true;
  return run;
}

// The DOM of url as serialized after virtual_time_ms of its scripts, laid
// out in a width x height CSS px window.
inline BrowserRun DumpDom(const std::string& url, int width, int height, int virtual_time_ms,
                          const std::filesystem::path& work_dir) {
  return RunHeadlessChromium(
      url, {"--dump-dom", "--window-size=" + std::to_string(width) + "," + std::to_string(height)},
      virtual_time_ms, work_dir, "dump_dom");
}

// A PNG screenshot of url's viewport (width x height CSS px) after
// virtual_time_ms of its scripts.
inline BrowserRun Screenshot(const std::string& url, const std::filesystem::path& png, int width,
                             int height, int virtual_time_ms,
                             const std::filesystem::path& work_dir) {
  return RunHeadlessChromium(
      url,
      {"--screenshot=" + png.string(),
       "--window-size=" + std::to_string(width) + "," + std::to_string(height)},
      virtual_time_ms, work_dir, "screenshot");
}

}  // namespace groundline::testing

// Skips the current test, with the reason, when no Chromium is installed.
#define GROUNDLINE_REQUIRE_CHROMIUM()                                                         \
  do {                                                                                        \
    if (::groundline::testing::FindChromium().empty()) {                                      \
      GTEST_SKIP() << "headless browser absent: no `chromium` in PATH (install Debian's "     \
                      "chromium, scripts/setup.sh, or set GROUNDLINE_CHROMIUM to a Chromium " \
                      "executable)";                                                          \
    }                                                                                         \
  } while (0)

#endif  // GROUNDLINE_TESTS_SUPPORT_HEADLESS_CHROMIUM_H_
