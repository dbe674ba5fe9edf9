// The closing block every dataset replay writes into DIR/summary.json: the
// keyframes' accuracy against ground truth (also printed) and the run's wall
// time, CPU time and peak memory (docs/metrics.md).
#ifndef GROUNDLINE_TOOLS_RUN_SUMMARY_H_
#define GROUNDLINE_TOOLS_RUN_SUMMARY_H_

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

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

// The ways a run can be other than it seems (an empty atlas, streams that
// do not overlap, skipped input lines, covariances far from the errors):
// each is printed to stderr as it is found ("groundline <command>: warning:
// ...") and listed in summary.json under "warnings" as {kind, message}.
class RunWarnings {
 public:
  explicit RunWarnings(std::string command) : command_(std::move(command)) {}
  void Add(const std::string& kind, const std::string& message);
  std::size_t size() const { return warnings_.size(); }
  bool Has(const std::string& kind) const;
  nlohmann::ordered_json Json() const;

 private:
  std::string command_;
  std::vector<std::pair<std::string, std::string>> warnings_;
};

// A stream's time span, for CheckStreamSpans.
struct StreamSpan {
  std::string name;  // "wheel encoders", "camera frames", "LiDAR scans"
  double first_s = 0.0;
  double last_s = 0.0;
  double period_s = 0.0;  // nominal, from the sensor's rate
};

// Adds a "stream_spans" warning when a stream starts later or ends earlier
// than another by more than 1 s plus two of its periods: the estimate over
// the difference rests on fewer sensors than the run claims.
void CheckStreamSpans(const std::vector<StreamSpan>& spans, RunWarnings* warnings);

// The NEES band a consistent estimator stays in: a mean beyond 10x the
// degrees of freedom (or below a tenth of them) means covariances that do
// not describe the errors.
inline constexpr double kNeesWarnFactor = 10.0;

// Adds "accuracy" (ComputeTrajectoryErrors of keyframes against ground_truth,
// every metric printed to stdout under a diagnostics heading) when
// ground_truth is not empty, with a "nees_out_of_band" warning when
// check_nees, at least 30 poses carry a covariance and their mean NEES
// (3 dof) is outside [3 / kNeesWarnFactor, 3 kNeesWarnFactor]; then "warnings", "wall_s", "cpu_s"
// and "peak_rss_mb", and writes summary to out_dir/summary.json atomically. Errors name the failing
// step or file.
core::Status FinishRunSummary(const core::Trajectory& keyframes,
                              const core::Trajectory& ground_truth, bool check_nees,
                              const RunClock& clock, const std::filesystem::path& out_dir,
                              RunWarnings* warnings, nlohmann::ordered_json* summary);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_RUN_SUMMARY_H_
