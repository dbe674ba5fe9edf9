// Relative pose error (RPE), declared in trajectory_metrics.h.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "groundline/core/angles.h"
#include "groundline/core/trajectory_metrics.h"

namespace groundline::core {
namespace {

// Index j > i of the partner of pair i, or pairs.size() if there is none.
// `path_m` is the cumulative reference path length at each pair.
std::size_t Partner(std::size_t i, const std::vector<double>& path_m, const RpeOptions& options,
                    std::size_t start) {
  const std::size_t n = path_m.size();
  if (options.unit == RpeDeltaUnit::kFrames) {
    const std::size_t j = i + static_cast<std::size_t>(std::llround(options.delta));
    return j < n ? j : n;
  }
  std::size_t j = std::max(start, i + 1);
  while (j < n && path_m[j] - path_m[i] < options.delta) ++j;
  return j;
}

}  // namespace

Status RpeOptions::Validate() const {
  if (unit == RpeDeltaUnit::kFrames) {
    if (!(delta >= 1.0) || !std::isfinite(delta) || delta != std::floor(delta)) {
      return Status::Error("RPE delta in frames must be a positive integer, got " +
                           std::to_string(delta));
    }
  } else if (!(delta > 0.0) || !std::isfinite(delta)) {
    return Status::Error("RPE delta in metres must be finite and > 0 [m], got " +
                         std::to_string(delta));
  }
  return Status::Ok();
}

Result<RpeSummary> ComputeRpe(const std::vector<PosePair>& pairs, const RpeOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  std::vector<double> path_m(pairs.size(), 0.0);
  for (std::size_t i = 1; i < pairs.size(); ++i) {
    path_m[i] = path_m[i - 1] +
                (pairs[i].T_map_ref.translation() - pairs[i - 1].T_map_ref.translation()).norm();
  }
  std::vector<double> trans_m, rot_deg;
  std::size_t j = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    // The partner index never decreases with i for a distance delta.
    j = Partner(i, path_m, options, j);
    if (j >= pairs.size()) break;
    const SE2 delta_ref = pairs[i].T_map_ref.Between(pairs[j].T_map_ref);
    const SE2 delta_est = pairs[i].T_map_est.Between(pairs[j].T_map_est);
    const SE2 error = delta_ref.Between(delta_est);
    trans_m.push_back(error.translation().norm());
    rot_deg.push_back(std::abs(error.yaw()) * kRadToDeg);
  }
  if (trans_m.empty()) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "RPE: no pose pair is %g %s apart (%zu matched poses, %.3f m of reference path); "
                  "choose a shorter delta",
                  options.delta, options.unit == RpeDeltaUnit::kFrames ? "frames" : "m",
                  pairs.size(), path_m.empty() ? 0.0 : path_m.back());
    return Status::Error(text);
  }
  RpeSummary summary;
  summary.options = options;
  summary.trans_m = ComputeErrorStats(std::move(trans_m));
  summary.rot_deg = ComputeErrorStats(std::move(rot_deg));
  return summary;
}

}  // namespace groundline::core
