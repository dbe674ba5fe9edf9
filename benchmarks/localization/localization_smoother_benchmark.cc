// The sliding-window smoother on simulated zone B driving (observations from
// the floor map at the true poses, not the extractor; one thread).
//   build/benchmarks/localization_smoother_benchmark
// BM_KeyframeUpdate: per-keyframe AddKeyframe time with a full 120 s window
// (after a warm-up that fills it);
// counters median_ms / p99_ms (wall) and cpu_median_ms / cpu_p99_ms (thread CPU).
// BM_LongDriveMemory/<minutes> (10, 60, 480 = 8 h; the 8 h run takes
// about 45 min of CPU, select it with --benchmark_filter): drives <minutes> of simulated time
// through the smoother and reports the resident set size at the half and at the end (rss_half_mb,
// rss_end_mb) and the largest window: flat RSS means no growth with run length (the atlas is fixed
// in localization mode).
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "groundline/localization/sliding_window_smoother.h"
#include "groundline/sim/floor_drive.h"
#include "groundline/sim/route.h"
#include "groundline/sim/sim_run.h"
#include "groundline/sim/zones.h"

namespace groundline::localization {
namespace {

struct Drive {
  core::FloorMap map;
  core::Trajectory trajectory;
};

const Drive& ZoneBDrive() {
  static const Drive drive = [] {
    const sim::World world = *sim::BuildZone(sim::Zone::kB, 1);
    sim::RouteOptions route_options;
    route_options.seed = 1;
    route_options.sample_rate_hz = 50.0;
    const sim::Route route = *sim::GenerateRoute(world, route_options);
    return Drive{sim::ToFloorMap(world), route.T_map_base};
  }();
  return drive;
}

double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

double ResidentSetMb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

sim::FloorDriveOptions DriveOptions(int loops) {
  sim::FloorDriveOptions options;
  options.seed = 1;
  options.loops = loops;
  options.observations.half_width_m = 1.25;  // the zone B aisle tapes in view
  return options;
}

void BM_KeyframeUpdate(benchmark::State& state) {
  const Drive& drive = ZoneBDrive();
  sim::FloorDrive floor_drive(drive.map, drive.trajectory, DriveOptions(100));
  SmootherOptions options;
  options.window_s = 120.0;
  SlidingWindowSmoother smoother(options, AtlasFromFloorMap(drive.map, {}));
  smoother.Initialize(floor_drive.Start().stamp_s, floor_drive.Start().pose,
                      Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
  sim::DriveKeyframe keyframe;
  const double start_s = floor_drive.Start().stamp_s;
  while (floor_drive.Next(&keyframe) && keyframe.stamp_s - start_s < options.window_s + 5.0) {
    (void)smoother.AddKeyframe(keyframe.stamp_s, keyframe.motion, keyframe.observations);
  }
  std::vector<double> wall_ms;
  std::vector<double> cpu_ms;
  for (auto _ : state) {
    state.PauseTiming();
    floor_drive.Next(&keyframe);
    state.ResumeTiming();
    const double cpu_start_ms = ThreadCpuMs();
    const auto health =
        smoother.AddKeyframe(keyframe.stamp_s, keyframe.motion, keyframe.observations);
    cpu_ms.push_back(ThreadCpuMs() - cpu_start_ms);
    benchmark::DoNotOptimize(health);
    wall_ms.push_back(health.ok() ? health->update_time_s * 1e3 : 0.0);
  }
  const auto percentile = [](std::vector<double> v, int p) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, v.size() * p / 100)];
  };
  // Wall time suffers from other processes on a shared machine; CPU time of
  // this thread is the cost of the update.
  state.counters["median_ms"] = percentile(wall_ms, 50);
  state.counters["p99_ms"] = percentile(wall_ms, 99);
  state.counters["cpu_median_ms"] = percentile(cpu_ms, 50);
  state.counters["cpu_p99_ms"] = percentile(cpu_ms, 99);
  state.counters["window"] = smoother.WindowSize();
}
BENCHMARK(BM_KeyframeUpdate)->Iterations(500)->Unit(benchmark::kMillisecond);

void BM_LongDriveMemory(benchmark::State& state) {
  const double duration_s = 60.0 * static_cast<double>(state.range(0));
  const Drive& drive = ZoneBDrive();
  for (auto _ : state) {
    sim::FloorDrive floor_drive(drive.map, drive.trajectory, DriveOptions(1000));
    SmootherOptions options;
    options.window_s = 120.0;
    options.max_iterations = 3;
    SlidingWindowSmoother smoother(options, AtlasFromFloorMap(drive.map, {}));
    smoother.Initialize(floor_drive.Start().stamp_s, floor_drive.Start().pose,
                        Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
    sim::DriveKeyframe keyframe;
    const double start_s = floor_drive.Start().stamp_s;
    double rss_half_mb = 0.0;
    int max_window = 0;
    long keyframes = 0;
    while (floor_drive.Next(&keyframe) && keyframe.stamp_s - start_s < duration_s) {
      const auto health =
          smoother.AddKeyframe(keyframe.stamp_s, keyframe.motion, keyframe.observations);
      if (health.ok()) max_window = std::max(max_window, health->window_size);
      if (rss_half_mb == 0.0 && keyframe.stamp_s - start_s >= 0.5 * duration_s) {
        rss_half_mb = ResidentSetMb();
      }
      ++keyframes;
    }
    state.counters["rss_half_mb"] = rss_half_mb;
    state.counters["rss_end_mb"] = ResidentSetMb();
    state.counters["max_window"] = max_window;
    state.counters["keyframes"] = static_cast<double>(keyframes);
  }
}
BENCHMARK(BM_LongDriveMemory)->Arg(10)->Arg(60)->Arg(480)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace groundline::localization
