// The stop conditions of a live capture loop (calibrate intrinsics/floor
// --live): Ctrl-C, a duration, or the end of a recorded source. While a
// LiveSession exists, SIGINT sets a flag instead of killing the process, so
// the loop finishes cleanly (solves what it has and writes its files); a
// second Ctrl-C, after the handler has been restored, kills as usual.
#ifndef GROUNDLINE_TOOLS_LIVE_SESSION_H_
#define GROUNDLINE_TOOLS_LIVE_SESSION_H_

#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include <memory>

#include <CLI/CLI.hpp>

#include "groundline/core/status.h"
#include "groundline/io/frame_source.h"
#include "png_file.h"

namespace groundline::tools {

class LiveSession {
 public:
  // duration_s <= 0: no time limit.
  explicit LiveSession(double duration_s)
      : duration_s_(duration_s), start_(std::chrono::steady_clock::now()) {
    Interrupted() = 0;
    struct sigaction action {};
    action.sa_handler = [](int) { Interrupted() = 1; };
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;  // a second Ctrl-C kills
    sigaction(SIGINT, &action, &previous_);
  }
  ~LiveSession() { sigaction(SIGINT, &previous_, nullptr); }
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;

  double ElapsedS() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  // Why the loop should stop now ("interrupted (Ctrl-C)", "--duration 60 s
  // reached"), or "" to go on.
  std::string StopReason() const {
    if (Interrupted() != 0) return "interrupted (Ctrl-C)";
    if (duration_s_ > 0.0 && ElapsedS() >= duration_s_) {
      return "--duration " + std::to_string(static_cast<int>(duration_s_)) + " s reached";
    }
    return "";
  }

 private:
  static volatile std::sig_atomic_t& Interrupted() {
    static volatile std::sig_atomic_t flag = 0;
    return flag;
  }
  double duration_s_;
  std::chrono::steady_clock::time_point start_;
  struct sigaction previous_ {};
};

// The options every live flow shares: --duration, --frame-timeout and
// --save-frames (whose meaning of "not given" differs per flow, hence its help).
inline void AddLiveCaptureOptions(CLI::App* cmd, double* duration_s, double* timeout_s,
                                  std::string* save_frames, const std::string& save_frames_help) {
  cmd->add_option("--duration", *duration_s, "Live: stop after this many seconds (0: no limit)")
      ->capture_default_str();
  cmd->add_option("--frame-timeout", *timeout_s,
                  "Live: seconds to wait for one frame before giving up")
      ->capture_default_str();
  cmd->add_option("--save-frames", *save_frames, "Live: " + save_frames_help);
}

// Opens the --live source with latest_only (the guidance is about the
// current view, so stale queued frames are dropped). On failure prints
// "COMMAND: --live: why" to stderr and returns null (exit code 2).
inline std::unique_ptr<io::FrameSource> OpenLiveSource(const std::string& uri,
                                                       const char* command) {
  io::FrameSourceOptions options;
  options.latest_only = true;
  core::Result<std::unique_ptr<io::FrameSource>> source = io::OpenFrameSource(uri, options);
  if (!source.ok()) {
    std::fprintf(stderr, "%s: --live: %s\n", command, source.message().c_str());
    return nullptr;
  }
  return std::move(*source);
}

// Writes a kept frame into DIR, atomically (DIR/tmp.NAME, then rename), under
// its own name, except that a lossy .jpg/.jpeg name becomes .png (a saved
// frame must decode to exactly the pixels that were used). Returns the file
// name written.
inline core::Result<std::string> SaveFrame(const std::filesystem::path& dir,
                                           const std::string& frame_name, const cv::Mat& grey) {
  std::filesystem::path file(frame_name);
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".jpg" || ext == ".jpeg" || ext.empty()) file.replace_extension(".png");
  const std::string name = file.filename().string();
  if (core::Status s = WritePngAtomically(dir / name, grey); !s.ok()) {
    return s.WithContext("cannot save the frame");
  }
  return name;
}

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LIVE_SESSION_H_
