// Speed of the IPM and of the steerable ridge filter, one thread.
//   build/benchmarks/perception_bev_benchmark --benchmark_repetitions=5
// The reference camera (OPENCV8, fx 1132 px, 1280 x 1024 grey) on the
// reference mount, the default BEV grid (x 0.6-2.4 m, y +-1 m, 1 cm cells:
// 180 x 200 cells).
//   BM_RemapToBev            BevRemap::Apply, fixed-point maps (arg 1) or float maps (arg 0)
//   BM_WarpPerspectiveToBev  the OpenCV baseline: one cv::warpPerspective of the
//                            same frame to the same grid (pinhole, no undistortion)
//   BM_SteerableRidge        Hessian (3 sepFilter2D), arg 1: + eigen analysis (AnalyzeRidges)
//   BM_RebuildRemapTable     BevRemap::Rebuild after a pitch change (mrcal projection)
#include <benchmark/benchmark.h>

#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "groundline/perception/bev_remap.h"
#include "groundline/perception/steerable_ridge.h"

namespace groundline::perception {
namespace {

calibration::CameraModel ReferenceCamera() {
  return *calibration::CameraModel::Create(
      "LENSMODEL_OPENCV8",
      {1132.0, 1131.0, 639.5, 511.5, -0.12, 0.05, 0.0006, -0.0004, 0.0, 0.004, -0.002, 0.001}, 1280,
      1024);
}

cv::Mat GreyFrame() {
  cv::Mat noise(1024, 1280, CV_8U), frame;
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(noise, frame, cv::Size(0, 0), 2.0);
  return frame;
}

void BM_RemapToBev(benchmark::State& state) {
  cv::setNumThreads(1);
  BevRemap::Options options;
  options.fixed_point = state.range(0) != 0;
  const BevRemap remap(ReferenceCamera(), calibration::CameraMount{}, options);
  const cv::Mat frame = GreyFrame();
  cv::Mat bev;
  for (auto _ : state) {
    remap.Apply(frame, &bev);
    benchmark::DoNotOptimize(bev.data);
  }
  state.counters["valid_cells"] = remap.valid_cells();
}
BENCHMARK(BM_RemapToBev)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);

void BM_WarpPerspectiveToBev(benchmark::State& state) {
  cv::setNumThreads(1);
  const calibration::CameraModel camera = ReferenceCamera();
  const BevGrid grid(BevGridOptions{});
  const cv::Mat frame = GreyFrame();
  cv::Mat bev;
  for (auto _ : state) {
    WarpToBevPinhole(frame, grid, calibration::CameraMount{}, camera.K(), &bev);
    benchmark::DoNotOptimize(bev.data);
  }
}
BENCHMARK(BM_WarpPerspectiveToBev)->Unit(benchmark::kMicrosecond);

void BM_SteerableRidge(benchmark::State& state) {
  cv::setNumThreads(1);
  const BevRemap remap(ReferenceCamera(), calibration::CameraMount{}, BevRemap::Options{});
  cv::Mat bev;
  remap.Apply(GreyFrame(), &bev);
  const SteerableRidgeFilter filter(SteerableRidgeOptions{});
  HessianImages hessian;
  RidgeImages ridges;
  for (auto _ : state) {
    filter.Compute(bev, &hessian);
    if (state.range(0) != 0) AnalyzeRidges(hessian, &ridges);
    benchmark::DoNotOptimize(hessian.uu.data);
  }
}
BENCHMARK(BM_SteerableRidge)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_RebuildRemapTable(benchmark::State& state) {
  cv::setNumThreads(1);
  calibration::CameraMount mount;
  BevRemap remap(ReferenceCamera(), mount, BevRemap::Options{});
  int k = 0;
  for (auto _ : state) {
    mount.pitch_rad = (42.4 + 0.01 * (k++ % 7)) * std::numbers::pi / 180.0;
    remap.Rebuild(mount);
    benchmark::DoNotOptimize(remap.valid_cells());
  }
}
BENCHMARK(BM_RebuildRemapTable)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace groundline::perception
