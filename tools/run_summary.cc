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

void RunWarnings::Add(const std::string& kind, const std::string& message) {
  std::fprintf(stderr, "groundline %s: warning: %s\n", command_.c_str(), message.c_str());
  warnings_.emplace_back(kind, message);
}

bool RunWarnings::Has(const std::string& kind) const {
  for (const auto& [k, message] : warnings_) {
    if (k == kind) return true;
  }
  return false;
}

nlohmann::ordered_json RunWarnings::Json() const {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& [kind, message] : warnings_) {
    list.push_back({{"kind", kind}, {"message", message}});
  }
  return list;
}

void CheckStreamSpans(const std::vector<StreamSpan>& spans, RunWarnings* warnings) {
  if (spans.size() < 2) return;
  const StreamSpan* earliest = &spans[0];
  const StreamSpan* latest = &spans[0];
  for (const StreamSpan& s : spans) {
    if (s.first_s < earliest->first_s) earliest = &s;
    if (s.last_s > latest->last_s) latest = &s;
  }
  std::string list, problems;
  char text[256];
  for (const StreamSpan& s : spans) {
    std::snprintf(text, sizeof(text), "%s%s %.2f-%.2f s", list.empty() ? "" : ", ", s.name.c_str(),
                  s.first_s, s.last_s);
    list += text;
    const double tolerance_s = 1.0 + 2.0 * s.period_s;
    if (latest->last_s - s.last_s > tolerance_s) {
      std::snprintf(text, sizeof(text), "%sthe %s end %.1f s before the %s",
                    problems.empty() ? "" : "; ", s.name.c_str(), latest->last_s - s.last_s,
                    latest->name.c_str());
      problems += text;
    }
    if (s.first_s - earliest->first_s > tolerance_s) {
      std::snprintf(text, sizeof(text), "%sthe %s start %.1f s after the %s",
                    problems.empty() ? "" : "; ", s.name.c_str(), s.first_s - earliest->first_s,
                    earliest->name.c_str());
      problems += text;
    }
  }
  if (problems.empty()) return;
  warnings->Add("stream_spans", "the streams do not cover the same time span (" + list +
                                    "): " + problems +
                                    "; the estimate over the difference rests on fewer sensors");
}

core::Status FinishRunSummary(const core::Trajectory& keyframes,
                              const core::Trajectory& ground_truth, bool check_nees,
                              const RunClock& clock, const std::filesystem::path& out_dir,
                              RunWarnings* warnings, nlohmann::ordered_json* summary) {
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
    // Below 30 poses the mean of a chi-square is too noisy to judge.
    if (check_nees && errors->nees && errors->nees->n >= 30) {
      constexpr double kDof = 3.0;
      const double mean = errors->nees->mean;
      if (!(mean <= kNeesWarnFactor * kDof && mean >= kDof / kNeesWarnFactor)) {
        char text[320];
        std::snprintf(text, sizeof(text),
                      "the mean NEES against ground truth is %.3g, outside [%.1f, %.0f] (%.0f "
                      "expected): the covariances %s the errors",
                      mean, kDof / kNeesWarnFactor, kNeesWarnFactor * kDof, kDof,
                      mean > kDof ? "understate" : "overstate");
        warnings->Add("nees_out_of_band", text);
      }
    }
  }
  (*summary)["warnings"] = warnings->Json();
  (*summary)["wall_s"] = clock.WallSeconds();
  (*summary)["cpu_s"] = clock.CpuSeconds();
  (*summary)["peak_rss_mb"] = ProcessPeakRssMb();
  return core::WriteFileAtomically(out_dir / "summary.json", summary->dump(2) + "\n");
}

}  // namespace groundline::tools
