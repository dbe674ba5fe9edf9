// Throughput of the simulated floor camera (one thread).
//   build/benchmarks/sim_floor_camera_benchmark
// BM_FloorCameraAlongRoute renders 1280x1024 frames with every default
// nuisance on at poses along a zone's route (one frame every 0.5 s of driving,
// cycling through the loop); "frames_per_s" is the renderer's throughput on one
// core, without PNG encoding. BM_FloorCameraSetup is the one-off cost of the
// pixel-to-floor table (one mrcal unprojection per pixel).
#include <benchmark/benchmark.h>

#include "groundline/sim/floor_camera.h"
#include "groundline/sim/lidar.h"
#include "groundline/sim/route.h"
#include "groundline/sim/zones.h"

namespace groundline::sim {
namespace {

void BM_FloorCameraSetup(benchmark::State& state) {
  const World world = *BuildZone(Zone::kD, 1);
  const FloorCameraOptions camera;
  const calibration::CameraModel model = *camera.MakeCameraModel();
  for (auto _ : state) {
    benchmark::DoNotOptimize(FloorRenderer::Create(world, model, camera.mount, {}));
  }
}
BENCHMARK(BM_FloorCameraSetup)->Unit(benchmark::kMillisecond);

void BM_FloorCameraAlongRoute(benchmark::State& state) {
  const World world = *BuildZone(static_cast<Zone>(state.range(0)), 1);
  const core::Result<Route> route = GenerateRoute(world, RouteOptions{});
  if (!route.ok()) {
    state.SkipWithError(route.message().c_str());
    return;
  }
  const FloorCameraOptions camera;
  const core::Result<FloorRenderer> renderer =
      FloorRenderer::Create(world, *camera.MakeCameraModel(), camera.mount, {});
  const double t0 = route->T_map_base.front().stamp_s;
  const double span = route->T_map_base.back().stamp_s - t0;
  std::uint64_t k = 0;
  for (auto _ : state) {
    const double t = t0 + std::fmod(0.5 * static_cast<double>(k), span);
    const GreyImage image = renderer->Render(InterpolatePose(route->T_map_base, t), {1.5, 0.0}, k);
    benchmark::DoNotOptimize(image.pixels.data());
    ++k;
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(k), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FloorCameraAlongRoute)
    ->ArgName("zone")
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

}  // namespace
}  // namespace groundline::sim
