// Throughput of the simulated planar LiDAR and of the route generator.
//   build/benchmarks/sim_lidar_benchmark
// BM_LidarAlongRoute casts every scan of a 1.2 km loop at 15 Hz (about 12,000
// scans of 819 rays, with per-ray motion); its "scans_per_s" counter is the
// simulator's LiDAR throughput on one core.
#include <benchmark/benchmark.h>

#include <numbers>

#include "groundline/sim/lidar.h"
#include "groundline/sim/route.h"
#include "groundline/sim/zones.h"

namespace groundline::sim {
namespace {

const World& ZoneWorld(Zone zone) {
  static const World worlds[] = {*BuildZone(Zone::kA, 1), *BuildZone(Zone::kB, 1),
                                 *BuildZone(Zone::kC, 1), *BuildZone(Zone::kD, 1)};
  return worlds[static_cast<int>(zone)];
}

void BM_LidarScanInAisle(benchmark::State& state) {
  const ZoneBOptions zone;
  const PlanarLidar lidar(ZoneWorld(Zone::kB), LidarOptions{});
  const core::SE2 pose(zone.AisleCenterXM(10), zone.RackStartYM() + 40.0, std::numbers::pi / 2);
  std::uint64_t k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(lidar.Scan(pose, 0.0, k++));
  state.counters["scans_per_s"] =
      benchmark::Counter(static_cast<double>(k), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_LidarScanInAisle);

void BM_LidarAlongRoute(benchmark::State& state) {
  const Zone zone = static_cast<Zone>(state.range(0));
  const World& world = ZoneWorld(zone);
  const core::Result<Route> route = GenerateRoute(world, RouteOptions{});
  if (!route.ok()) {
    state.SkipWithError(route.message().c_str());
    return;
  }
  const PlanarLidar lidar(world, LidarOptions{});
  std::size_t scans = 0;
  for (auto _ : state) {
    const std::vector<LaserScan> all = SimulateScans(lidar, route->T_map_base);
    scans += all.size();
    benchmark::DoNotOptimize(all.data());
  }
  state.counters["scans_per_s"] =
      benchmark::Counter(static_cast<double>(scans), benchmark::Counter::kIsRate);
  state.counters["scans_per_loop"] =
      static_cast<double>(scans) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_LidarAlongRoute)->DenseRange(0, 3)->Unit(benchmark::kSecond)->Iterations(1);

void BM_GenerateRoute(benchmark::State& state) {
  const World& world = ZoneWorld(static_cast<Zone>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(GenerateRoute(world, RouteOptions{}).ok());
}
BENCHMARK(BM_GenerateRoute)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace groundline::sim
