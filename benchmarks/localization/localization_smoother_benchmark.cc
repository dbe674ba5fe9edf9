// The sliding-window smoother on simulated zone B driving (observations from
// the floor map at the true poses, not the extractor; one thread).
//   build/benchmarks/localization_smoother_benchmark
// BM_KeyframeUpdate: per-keyframe AddKeyframe time with a full 120 s window
// (after a warm-up that fills it);
// counters median_ms / p99_ms (wall) and cpu_median_ms / cpu_p99_ms (thread CPU).
// BM_KeyframeUpdate/0 is the chain solver, /1 Ceres on the same window (the reference).
// BM_LongDrive/<minutes> (10, 60, 480 = 8 h; select with --benchmark_filter): drives <minutes> of
// simulated time through the smoother and reports the resident set size at 10 min and every hour
// and the NEES consistency of the reported covariance (see below): flat RSS means no growth with
// run length (the atlas is fixed in localization mode).
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <cstdio>
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
    // A closed loop: FloorDrive repeats it, and an open route's end would
    // jump back to its start (a teleport the odometry reports as one step).
    route_options.closed_loop = true;
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
  // The zone B aisle tapes in view: ~2.1 lines per keyframe on this route
  // (a view 6 m wide and 3.5 m deep still gives only 2.5: zone B's markings
  // are the aisle tapes).
  options.observations.half_width_m = 1.25;
  return options;
}

double Percentile(std::vector<double> v, int p) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[std::min(v.size() - 1, v.size() * p / 100)];
}

// Arg 0: the chain solver (SmootherSolver::kChain); 1: Ceres on the same window (kCeres).
void BM_KeyframeUpdate(benchmark::State& state) {
  const Drive& drive = ZoneBDrive();
  sim::FloorDrive floor_drive(drive.map, drive.trajectory, DriveOptions(100));
  SmootherOptions options;
  options.window_s = 120.0;
  options.solver = state.range(0) == 0 ? SmootherSolver::kChain : SmootherSolver::kCeres;
  state.SetLabel(state.range(0) == 0 ? "chain" : "ceres");
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
  std::vector<double> iterations;
  double lines_used = 0.0;
  double lines_observed = 0.0;
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
    iterations.push_back(health.ok() ? health->iterations : 0);
    lines_used += health.ok() ? health->lines_used : 0;
    lines_observed += health.ok() ? health->lines_observed : 0;
  }
  const auto percentile = Percentile;
  // Wall time suffers from other processes on a shared machine; CPU time of
  // this thread is the cost of the update.
  state.counters["median_ms"] = percentile(wall_ms, 50);
  state.counters["p99_ms"] = percentile(wall_ms, 99);
  state.counters["cpu_median_ms"] = percentile(cpu_ms, 50);
  state.counters["cpu_p99_ms"] = percentile(cpu_ms, 99);
  state.counters["window"] = smoother.WindowSize();
  state.counters["iterations_median"] = percentile(iterations, 50);
  state.counters["iterations_p99"] = percentile(iterations, 99);
  state.counters["iterations_max"] = *std::max_element(iterations.begin(), iterations.end());
  state.counters["lines_used"] = lines_used / static_cast<double>(wall_ms.size());
  state.counters["lines_observed"] = lines_observed / static_cast<double>(wall_ms.size());
}
BENCHMARK(BM_KeyframeUpdate)->Arg(0)->Arg(1)->Iterations(500)->Unit(benchmark::kMillisecond);

// Drives <minutes> of simulated time (keyframes only, no rendering) and
// reports the resident set size at 10 min and at every hour (rss_10min_mb,
// rss_1h_mb ... rss_8h_mb), the largest window, and the consistency of the
// reported covariance against the truth: the fraction of keyframes whose
// pose NEES (3 dof, e = Log(T_est^-1 T_true)) lies in the two-sided 95 %
// chi-square band [0.216, 9.348] (nees_in_band), and the mean NEES (3 when
// consistent).
void BM_LongDrive(benchmark::State& state) {
  const double duration_s = 60.0 * static_cast<double>(state.range(0));
  const Drive& drive = ZoneBDrive();
  for (auto _ : state) {
    sim::FloorDriveOptions drive_options = DriveOptions(100000);
    if (state.range(1) == 0) {  // the odometry's noise model only, no calibration error
      drive_options.distance_scale_error = 0.0;
      drive_options.rotation_scale_error = 0.0;
    }
    sim::FloorDrive floor_drive(drive.map, drive.trajectory, drive_options);
    SmootherOptions options;
    options.window_s = 120.0;
    SlidingWindowSmoother smoother(options, AtlasFromFloorMap(drive.map, {}));
    smoother.Initialize(floor_drive.Start().stamp_s, floor_drive.Start().pose,
                        Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
    sim::DriveKeyframe keyframe;
    const double start_s = floor_drive.Start().stamp_s;
    std::vector<double> marks_s = {600.0};
    for (int hour = 1; hour <= 8; ++hour) marks_s.push_back(3600.0 * hour);
    size_t next_mark = 0;
    int max_window = 0;
    long keyframes = 0;
    long in_band = 0;
    long errors = 0;
    double nees_sum = 0.0;
    while (floor_drive.Next(&keyframe) && keyframe.stamp_s - start_s < duration_s) {
      const auto health =
          smoother.AddKeyframe(keyframe.stamp_s, keyframe.motion, keyframe.observations);
      if (!health.ok()) {
        if (errors++ == 0) {
          std::fprintf(stderr, "first error at %.1f s: %s\n", keyframe.stamp_s - start_s,
                       health.status().message().c_str());
        }
        continue;
      }
      max_window = std::max(max_window, health->window_size);
      const PoseEstimate& latest = smoother.Latest();
      const Eigen::Vector3d e = keyframe.T_map_base_true.Minus(latest.T_map_base);
      const double nees = e.dot(latest.covariance.ldlt().solve(e));
      nees_sum += nees;
      in_band += (nees >= 0.2158 && nees <= 9.3484) ? 1 : 0;
      ++keyframes;
      if (next_mark < marks_s.size() && keyframe.stamp_s - start_s >= marks_s[next_mark]) {
        const std::string name =
            next_mark == 0 ? "rss_10min_mb" : "rss_" + std::to_string(next_mark) + "h_mb";
        state.counters[name] = ResidentSetMb();
        ++next_mark;
      }
    }
    state.counters["rss_end_mb"] = ResidentSetMb();
    state.counters["errors"] = static_cast<double>(errors);
    state.counters["max_window"] = max_window;
    state.counters["keyframes"] = static_cast<double>(keyframes);
    state.counters["simulated_h"] = (keyframe.stamp_s - start_s) / 3600.0;
    state.counters["nees_in_band"] = static_cast<double>(in_band) / std::max(1L, keyframes);
    state.counters["nees_mean"] = nees_sum / std::max(1L, keyframes);
  }
}
// Args: minutes, and 1 with the simulated wheel calibration errors (0.2 %
// distance and rotation scale, not in the odometry covariance), 0 without.
BENCHMARK(BM_LongDrive)
    ->Args({10, 1})
    ->Args({10, 0})
    ->Args({60, 1})
    ->Args({480, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace groundline::localization
