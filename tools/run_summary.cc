#include "run_summary.h"

#include <cstdio>
#include <string>

#include "groundline/core/atomic_file.h"
#include "groundline/core/metric_fields.h"
#include "groundline/core/trajectory_metrics.h"
#include "run_resources.h"

namespace groundline::tools {

RunClock::RunClock()
    : wall_start_(std::chrono::steady_clock::now()), cpu_start_s_(ProcessCpuSeconds()) {}

double RunClock::WallSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
}

double RunClock::CpuSeconds() const { return ProcessCpuSeconds() - cpu_start_s_; }

core::Status FinishRunSummary(const core::Trajectory& keyframes,
                              const core::Trajectory& ground_truth, const RunClock& clock,
                              const std::filesystem::path& out_dir,
                              nlohmann::ordered_json* summary) {
  if (!ground_truth.empty()) {
    core::Result<core::TrajectoryErrorSummary> errors =
        core::ComputeTrajectoryErrors(keyframes, ground_truth);
    if (!errors.ok()) {
      return core::Status::Error("evaluating against ground truth: " + errors.message());
    }
    std::printf(
        "diagnostics (ground truth, not available on a vehicle): accuracy of the keyframes "
        "(%zu poses matched):\n",
        errors->n_matched);
    nlohmann::ordered_json accuracy;
    for (const core::MetricField& f : core::MetricFields(*errors)) {
      accuracy[f.key] = f.value;
      if (!f.is_count) std::printf("  %-28s %10.4f\n", f.label.c_str(), f.value);
    }
    (*summary)["accuracy"] = accuracy;
  }
  (*summary)["wall_s"] = clock.WallSeconds();
  (*summary)["cpu_s"] = clock.CpuSeconds();
  (*summary)["peak_rss_mb"] = ProcessPeakRssMb();
  return core::WriteFileAtomically(out_dir / "summary.json", summary->dump(2) + "\n");
}

}  // namespace groundline::tools
