// The closing block every dataset replay writes into DIR/summary.json: the
// keyframes' accuracy against ground truth (also printed) and the run's wall
// time, CPU time and peak memory (EVAL.md, "what the eval outputs contain").
#ifndef GROUNDLINE_TOOLS_RUN_SUMMARY_H_
#define GROUNDLINE_TOOLS_RUN_SUMMARY_H_

#include <chrono>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"

namespace groundline::tools {

// Wall and CPU time since construction; start one at the top of a run.
class RunClock {
 public:
  RunClock();
  double WallSeconds() const;
  double CpuSeconds() const;

 private:
  std::chrono::steady_clock::time_point wall_start_;
  double cpu_start_s_;
};

// Adds "accuracy" (ComputeTrajectoryErrors of keyframes against ground_truth,
// every metric printed to stdout) when ground_truth is not empty, then
// "wall_s", "cpu_s" and "peak_rss_mb", and writes summary to
// out_dir/summary.json atomically. Errors name the failing step or file.
core::Status FinishRunSummary(const core::Trajectory& keyframes,
                              const core::Trajectory& ground_truth, const RunClock& clock,
                              const std::filesystem::path& out_dir,
                              nlohmann::ordered_json* summary);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_RUN_SUMMARY_H_
