// Speed of the whole per-frame line extraction, one thread, side by side with
// OpenCV's warpPerspective of the same frame to the same grid.
//   build/benchmarks/perception_lines_benchmark --benchmark_repetitions=5
// The frame: the reference camera (OPENCV5, 1280 x 1024 grey, the simulator's
// lens) on the reference mount looking at concrete (value noise) with a
// longitudinal tape, a transverse 20 cm stop bar and a dark joint.
//   BM_FrameToLines          BevRemap::Apply + LineExtractor::Extract with the buffers kept
//                            from frame to frame (as the service and the localizer
//                            run); args: BEV samples per cell along x across
//                            (extract and localize: 2 x 4)
//   BM_ExtractOnly           LineExtractor::Extract on the BEV; arg 1: with a kept
//                            ExtractionScratch, 0: buffers allocated per call
//   BM_WarpPerspectiveToBev  cv::warpPerspective (pinhole, no undistortion)
#include <benchmark/benchmark.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "groundline/calibration/floor_projection.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/line_extractor.h"

namespace groundline::perception {
namespace {

calibration::CameraModel ReferenceCamera() {
  return *calibration::CameraModel::Create(
      "LENSMODEL_OPENCV5", {1132.0, 1132.0, 643.0, 509.0, -0.05, 0.012, 2e-4, -1.5e-4, 0.0}, 1280,
      1024);
}

const cv::Mat& FloorFrame() {
  static const cv::Mat frame = [] {
    const calibration::FloorProjection projection(ReferenceCamera(), calibration::CameraMount{});
    cv::Mat noise(1024, 1280, CV_8S), image(1024, 1280, CV_8U);
    cv::RNG rng(5);
    rng.fill(noise, cv::RNG::NORMAL, 0, 6);
    for (int v = 0; v < 1024; ++v) {
      for (int u = 0; u < 1280; ++u) {
        core::Result<Eigen::Vector2d> p = projection.FloorPointOfPixel({u, v});
        double grey = 35.0;
        if (p.ok()) {
          grey = 80.0;
          if (std::abs(p->y() - 0.35) < 0.0375) grey = 170.0;
          if (std::abs(p->x() - 1.7) < 0.1 && p->y() < 0.35) grey = 200.0;
          if (std::abs(p->y() + 0.4) < 0.004) grey = 25.0;
        }
        image.at<std::uint8_t>(v, u) =
            cv::saturate_cast<std::uint8_t>(grey + noise.at<std::int8_t>(v, u));
      }
    }
    cv::GaussianBlur(image, image, cv::Size(0, 0), 0.7);
    return image;
  }();
  return frame;
}

void BM_FrameToLines(benchmark::State& state) {
  cv::setNumThreads(1);
  BevRemap::Options options;
  options.supersampling = static_cast<int>(state.range(0));
  options.supersampling_across = static_cast<int>(state.range(1));
  const BevRemap remap(ReferenceCamera(), calibration::CameraMount{}, options);
  const LineExtractor extractor(remap, LineExtractorOptions{});
  const cv::Mat& frame = FloorFrame();
  cv::Mat bev;
  ExtractionScratch scratch;
  size_t lines = 0;
  for (auto _ : state) {
    remap.Apply(frame, &bev);
    const LineExtraction out = extractor.Extract(bev, &scratch);
    lines = out.lines.size();
    benchmark::DoNotOptimize(lines);
  }
  state.counters["lines"] = static_cast<double>(lines);
}
// Args: BEV samples per cell along x across (groundline extract's default: 2 x 4).
BENCHMARK(BM_FrameToLines)
    ->Args({1, 1})
    ->Args({2, 2})
    ->Args({2, 4})
    ->Args({4, 4})
    ->Unit(benchmark::kMicrosecond);

void BM_ExtractOnly(benchmark::State& state) {
  cv::setNumThreads(1);
  const BevRemap remap(ReferenceCamera(), calibration::CameraMount{}, BevRemap::Options{});
  const LineExtractor extractor(remap, LineExtractorOptions{});
  cv::Mat bev;
  remap.Apply(FloorFrame(), &bev);
  ExtractionScratch scratch;
  const bool keep = state.range(0) != 0;
  for (auto _ : state) {
    const LineExtraction out = keep ? extractor.Extract(bev, &scratch) : extractor.Extract(bev);
    benchmark::DoNotOptimize(out.lines.data());
  }
}
BENCHMARK(BM_ExtractOnly)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_WarpPerspectiveToBev(benchmark::State& state) {
  cv::setNumThreads(1);
  const BevGrid grid(BevGridOptions{});
  const cv::Mat& frame = FloorFrame();
  cv::Mat bev;
  for (auto _ : state) {
    WarpToBevPinhole(frame, grid, calibration::CameraMount{}, ReferenceCamera().K(), &bev);
    benchmark::DoNotOptimize(bev.data);
  }
}
BENCHMARK(BM_WarpPerspectiveToBev)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace groundline::perception
