// WriteSimulatedImages: renders a run's camera frames and writes its
// calibration files (sim_run.h).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <thread>
#include <vector>

#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/core/atomic_file.h"
#include "groundline/sim/floor_nuisances.h"
#include "groundline/sim/lidar.h"
#include "groundline/sim/sim_run.h"

namespace groundline::sim {
namespace {

// Forward speed and yaw rate at the stamp, by central differences of the
// interpolated ground truth over +-5 ms.
BaseVelocity VelocityAt(const core::Trajectory& truth, double stamp_s) {
  constexpr double kH = 0.005;
  const core::SE2 a = InterpolatePose(truth, stamp_s - kH);
  const core::SE2 b = InterpolatePose(truth, stamp_s + kH);
  const core::Vector3 xi = a.Between(b).Log();
  return {xi.x() / (2.0 * kH), xi.z() / (2.0 * kH)};
}

core::Status WritePng(const std::filesystem::path& path, const GreyImage& image) {
  const cv::Mat mat(image.height_px, image.width_px, CV_8UC1,
                    const_cast<std::uint8_t*>(image.pixels.data()));
  std::vector<std::uint8_t> bytes;
  // Level 1: noisy floor images barely compress further and level 1 is ~4x faster.
  if (!cv::imencode(".png", mat, bytes, {cv::IMWRITE_PNG_COMPRESSION, 1})) {
    return core::Status::Error(path.string() + ": PNG encoding failed");
  }
  return core::WriteFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

// Renders frames [begin, end) on `threads` threads (with the world's moving
// obstacles as occluders when `occlusion`, and its static ones near the
// vehicle when `standing` too) and writes them into image_dir; progress(n)
// after every 20 frames written.
core::Status RenderFrames(const FloorRenderer& renderer, const World& world, bool occlusion,
                          bool standing, const core::Trajectory& truth,
                          const std::vector<core::ImageRecord>& frames, std::size_t begin,
                          std::size_t end, const std::filesystem::path& image_dir, int threads,
                          const std::function<void(std::size_t)>& progress) {
  std::atomic<std::size_t> next{begin};
  std::size_t written = 0;
  std::mutex mutex;  // guards first_error, written and progress
  core::Status first_error = core::Status::Ok();
  const auto worker = [&] {
    for (std::size_t k = next++; k < end; k = next++) {
      const core::ImageRecord& frame = frames[k];
      const core::SE2 pose = InterpolatePose(truth, frame.stamp_s);
      std::vector<Occluder> occluders;
      if (occlusion) {
        occluders = OccludersAt(world, frame.stamp_s);
        if (standing) {
          const std::vector<Occluder> near =
              StandingOccluders(world, pose.translation(), kStandingObjectRadiusM);
          occluders.insert(occluders.end(), near.begin(), near.end());
        }
      }
      const GreyImage image = renderer.Render(pose, VelocityAt(truth, frame.stamp_s), k, occluders);
      core::Status s = WritePng(image_dir / frame.file, image);
      std::lock_guard<std::mutex> lock(mutex);
      if (!s.ok() && first_error.ok()) first_error = s;
      if (!first_error.ok()) {
        next = end;
        return;
      }
      if (++written % 20 == 0) progress(20);
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < std::max(1, threads); ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  return first_error;
}

}  // namespace

core::Status WriteSimulatedImages(const std::filesystem::path& dir, const SimRun& run,
                                  const SimProgress& progress, int threads) {
  if (!run.camera || !run.dataset.manifest.camera) return core::Status::Ok();
  const SimCamera& cam = *run.camera;
  const core::CameraSensor& sensor = *run.dataset.manifest.camera;
  const auto report = [&progress](double fraction) {
    if (progress) progress("camera", fraction);
  };
  report(0.0);
  const std::filesystem::path image_dir =
      (dir / run.dataset.manifest.files.image_index).parent_path();
  const std::vector<core::ImageRecord>& frames = run.dataset.images;
  const std::vector<core::CameraExtrinsicsRecord>& mounts = run.dataset.ground_truth_extrinsics;
  std::atomic<std::size_t> done{0};
  // Frames are in stamp order, so each mount renders a contiguous range of
  // them, with its own renderer (the pixel table depends on the mount).
  for (std::size_t begin = 0; begin < frames.size();) {
    const std::size_t segment = mounts.empty() ? 0 : RecordAt(mounts, frames[begin].stamp_s);
    std::size_t end = begin + 1;
    while (end < frames.size() && !mounts.empty() &&
           RecordAt(mounts, frames[end].stamp_s) == segment) {
      ++end;
    }
    if (mounts.empty()) end = frames.size();
    const calibration::CameraMount mount = mounts.empty() ? cam.mount : ToMount(mounts[segment]);
    core::Result<FloorRenderer> renderer =
        FloorRenderer::Create(run.world, cam.model, mount, cam.render);
    if (!renderer.ok()) return renderer.status().WithContext("floor camera");
    if (core::Status s =
            RenderFrames(*renderer, run.world, cam.render.occlusion, cam.render.standing_objects,
                         run.route.T_map_base, frames, begin, end, image_dir, threads,
                         [&](std::size_t n) {
                           const std::size_t total = done += n;
                           report(static_cast<double>(total) / static_cast<double>(frames.size()));
                         });
        !s.ok()) {
      return s.WithContext("writing the camera images");
    }
    begin = end;
  }

  if (core::Status s = calibration::WriteOpenCvCalibration(dir / sensor.intrinsics_file, cam.model);
      !s.ok()) {
    return s.WithContext("writing the camera intrinsics");
  }
  if (core::Status s = calibration::WriteCameraMountYaml(cam.mount, dir / sensor.extrinsics_file);
      !s.ok()) {
    return s.WithContext("writing the camera extrinsics");
  }
  report(1.0);
  return core::Status::Ok();
}

}  // namespace groundline::sim
