// The camera mount's self-calibration per frame (calibration/
// mount_self_calibration.h) on the synthetic aisle's floor texture: 60
// patches per frame, 5 frames a second at 1.4 m/s, no marking in view (every
// frame pair has texture, the most work a frame can bring). Side by side in
// one run: with the frame-pair step check (quick_step_frames, the preset)
// and without it, so that its cost is a ratio on the same machine.
#include <benchmark/benchmark.h>

#include <vector>

#include "synthetic_aisle.h"
#include "groundline/calibration/mount_self_calibration.h"

namespace {

using groundline::calibration::CameraMount;
using groundline::calibration::MountFrame;
using groundline::calibration::MountSelfCalibrationOptions;
using groundline::calibration::MountSelfCalibrator;

// 30 s of driving, made once.
const std::vector<MountFrame>& Frames() {
  static const std::vector<MountFrame> frames = [] {
    groundline::testing_aisle::Drive d;
    d.texture_points = 60;
    d.texture_sigma_m = 0.001;
    d.rate_hz = 5.0;
    d.speed_mps = 1.4;
    const CameraMount mount;
    std::vector<MountFrame> out;
    for (double t = 0.0; t < 30.0; t += 1.0 / d.rate_hz)
      out.push_back(groundline::testing_aisle::MakeFrame(d, t, mount, mount));
    return out;
  }();
  return frames;
}

// Arg: quick_step_frames (0: off).
void BM_MountSelfCalibratorPerFrame(benchmark::State& state) {
  MountSelfCalibrationOptions options;
  options.quick_step_frames = static_cast<int>(state.range(0));
  const std::vector<MountFrame>& frames = Frames();
  for (auto _ : state) {
    MountSelfCalibrator calibrator(CameraMount{}, options);
    for (const MountFrame& f : frames) benchmark::DoNotOptimize(calibrator.AddFrame(f));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(frames.size()));
  state.SetLabel(options.quick_step_frames > 0 ? "with the frame-pair step check"
                                               : "windows only");
}
BENCHMARK(BM_MountSelfCalibratorPerFrame)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
