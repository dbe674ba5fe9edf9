// `groundline calibrate floor --live URI`: frames from a camera (or a
// recorded folder), the layout's tags detected in each, the frames that add
// views of a tag kept (calibration/tag_coverage.h) and written to a folder,
// which tags are still missing printed after each kept frame, then the
// folder flow's solve on the kept frames.
#include <cstdio>
#include <filesystem>

#include "calibrate_floor.h"
#include "groundline/calibration/board_detection.h"
#include "groundline/calibration/tag_coverage.h"
#include "groundline/io/frame_source.h"
#include "live_session.h"

namespace groundline::tools {

int RunCalibrateFloorLive(const CalibrateFloorFlags& flags, const calibration::TagLayout& layout,
                          const calibration::CameraModel& camera,
                          const calibration::FloorCalibrationOptions& options) {
  using namespace calibration;
  const char* kName = "groundline calibrate floor --live";
  if (flags.frames_per_tag < 1 || flags.max_frames < 0 || flags.duration_s < 0.0 ||
      !(flags.timeout_s > 0.0)) {
    std::fprintf(stderr,
                 "%s: --frames-per-tag must be >= 1, --max-frames and --duration >= 0, "
                 "--frame-timeout > 0\n",
                 kName);
    return 2;
  }
  const std::unique_ptr<io::FrameSource> source = OpenLiveSource(flags.live, kName);
  if (source == nullptr) return 2;
  io::FrameSource& frames = *source;
  if (layout.frame == TagLayoutFrame::kFloor && frames.IsLive()) {
    std::fprintf(stderr,
                 "%s: %s has frame: floor, which needs the vehicle's surveyed pose of every "
                 "image; from a camera use a layout with frame: base_link (vehicle standing "
                 "still, tags surveyed relative to it; docs/tag_layout.md)\n",
                 kName, flags.layout.c_str());
    return 2;
  }
  const std::filesystem::path frames_dir = flags.save_frames.empty()
                                               ? std::filesystem::path(flags.out) / "frames"
                                               : std::filesystem::path(flags.save_frames);
  std::error_code ec;
  if (std::filesystem::exists(frames_dir, ec) && !std::filesystem::is_empty(frames_dir, ec)) {
    std::fprintf(stderr, "%s: %s is not empty; the kept frames need an empty or new directory\n",
                 kName, frames_dir.c_str());
    return 2;
  }
  std::printf(
      "%s: %s; %zu tags in %s. Point the camera at the tags; Ctrl-C stops and solves "
      "what was kept.\n",
      kName, frames.Describe().c_str(), layout.tags.size(), flags.layout.c_str());
  std::fflush(stdout);

  TagCoverage coverage(layout, flags.frames_per_tag);
  TagLayout kept_layout = layout;
  kept_layout.vehicle_poses.clear();
  std::string stop;
  double last_rejection_s = -1e9;
  LiveSession session(flags.duration_s);
  for (;;) {
    if (stop = session.StopReason(); !stop.empty()) break;
    if (flags.max_frames > 0 && coverage.frames() >= flags.max_frames) {
      stop = "--max-frames " + std::to_string(flags.max_frames) + " reached";
      break;
    }
    core::Result<std::optional<io::Frame>> next = frames.Next(flags.timeout_s);
    if (!next.ok()) {
      if (!session.StopReason().empty()) continue;
      std::fprintf(stderr, "%s: %s\n", kName, next.message().c_str());
      return 1;
    }
    if (!next->has_value()) {
      stop = "end of " + frames.Describe();
      break;
    }
    const io::Frame& frame = **next;
    const auto reject = [&](const std::string& reason) {
      if (frames.IsLive() && session.ElapsedS() - last_rejection_s < 1.0) return;
      last_rejection_s = session.ElapsedS();
      std::printf("  %s: %s\n", frame.name.c_str(), reason.c_str());
      std::fflush(stdout);
    };
    if (frame.grey.cols != camera.width_px() || frame.grey.rows != camera.height_px()) {
      std::fprintf(stderr, "%s: %s is %dx%d but the camera model is %dx%d\n", kName,
                   frame.name.c_str(), frame.grey.cols, frame.grey.rows, camera.width_px(),
                   camera.height_px());
      return 1;
    }
    const VehiclePose* pose = nullptr;
    if (layout.frame == TagLayoutFrame::kFloor) {
      pose = layout.FindPose(frame.name);
      if (pose == nullptr) {
        reject("no surveyed vehicle pose for this image in the layout; skipped");
        continue;
      }
    }
    std::vector<int> ids;
    for (const TagDetection& d : DetectTags(frame.grey, options.detector)) ids.push_back(d.id);
    const TagCoverage::Verdict verdict = coverage.Consider(ids);
    if (!verdict.kept) {
      reject(verdict.reason);
      continue;
    }
    core::Result<std::string> saved = SaveFrame(frames_dir, frame.name, frame.grey);
    if (!saved.ok()) {
      std::fprintf(stderr, "%s: %s\n", kName, saved.message().c_str());
      return 1;
    }
    if (pose != nullptr) kept_layout.vehicle_poses.push_back({*saved, pose->T_floor_base});
    std::printf("[frame %d] %s %s\n  %s\n", coverage.frames(), saved->c_str(),
                verdict.reason.c_str(), coverage.StatusLine().c_str());
    for (const std::string& m : coverage.Missing()) std::printf("  still missing: %s\n", m.c_str());
    std::fflush(stdout);
    if (coverage.Complete()) {
      stop = "coverage complete";
      break;
    }
  }
  std::printf("%s: stopped: %s; %d frames kept in %s\n", kName, stop.c_str(), coverage.frames(),
              frames_dir.c_str());
  for (const std::string& r : frames.stats().skipped_reasons) {
    std::fprintf(stderr, "  %s\n", r.c_str());
  }
  if (!coverage.Complete()) {
    std::printf("  coverage incomplete (%s), solving anyway; still missing:\n",
                coverage.StatusLine().c_str());
    for (const std::string& m : coverage.Missing()) std::printf("    %s\n", m.c_str());
  }
  if (coverage.frames() == 0) {
    std::fprintf(stderr, "%s: no frame showed a tag of the layout; nothing to solve\n", kName);
    return 1;
  }
  return SolveAndReportFloor(flags, kept_layout, camera, frames_dir, options);
}

}  // namespace groundline::tools
