// The checks of `groundline localize` (localize_checks.h).
#include "localize_checks.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "groundline/core/text_parse.h"
#include "json_number.h"

namespace groundline::tools {

namespace fs = std::filesystem;
namespace loc = localization;

namespace {

// Beyond any warehouse's map frame, metres.
constexpr double kMaxMapCoordinateM = 1e5;

}  // namespace

void CheckLocalizeFlags(bool relocalize, const std::string& mode,
                        const std::vector<double>& initial_pose, const std::vector<double>& near) {
  const auto got = [](const std::vector<double>& values) {
    std::string text;
    for (double v : values) text += (text.empty() ? "" : " ") + core::FormatShortestDouble(v);
    return text;
  };
  const auto coordinate_ok = [](double v) {
    return std::isfinite(v) && std::abs(v) <= kMaxMapCoordinateM;
  };
  const std::vector<double>& p = initial_pose;
  if (p.size() == 3 && !(coordinate_ok(p[0]) && coordinate_ok(p[1]) && std::isfinite(p[2]) &&
                         std::abs(p[2]) <= 360.0)) {
    throw CLI::ValidationError(
        "--initial-pose",
        "expected X_M Y_M YAW_DEG with x and y finite in [-100000, 100000] m "
        "and yaw finite in [-360, 360] deg; got " +
            got(p));
  }
  if (relocalize && mode != "lines") {
    throw CLI::ValidationError("--relocalize",
                               "needs an atlas to recognize: use it with --mode lines");
  }
  if (!near.empty() && !relocalize) {
    throw CLI::ValidationError("--near", "is a hint for --relocalize: use it with --relocalize");
  }
  const std::vector<double>& n = near;
  if (!n.empty() &&
      !(coordinate_ok(n[0]) && coordinate_ok(n[1]) &&
        (n.size() < 3 || (std::isfinite(n[2]) && n[2] > 0.0 && n[2] <= kMaxMapCoordinateM)))) {
    throw CLI::ValidationError(
        "--near",
        "expected X_M Y_M [RADIUS_M] with x and y finite in [-100000, 100000] m and "
        "the radius finite in (0, 100000] m; got " +
            got(n));
  }
}

std::string HintNotSupported(const std::string& dataset, const Eigen::Vector2d& near_m,
                             const loc::RelocalizerStatus& s) {
  char text[640];
  std::snprintf(
      text, sizeof(text),
      "%s: --relocalize: the hint at (%.2f, %.2f) is not supported by the floor seen: the best "
      "hypothesis near it scores %.1f (%d of %d observations matched), the best overall %.1f "
      "(%d of %d), and that one's drive starts %.1f m from the hint (%zu frames disagreed with "
      "the hint); nothing committed. Check --near X_M Y_M [RADIUS_M] (where the drive starts), "
      "or give --initial-pose",
      dataset.c_str(), near_m.x(), near_m.y(), s.contradicted_best_log_likelihood,
      s.contradicted_best_matched, s.contradicted_best_matched + s.contradicted_best_unmatched,
      s.contradicted_overall_log_likelihood, s.contradicted_overall_matched,
      s.contradicted_overall_matched + s.contradicted_overall_unmatched,
      s.contradicted_overall_start_from_hint_m, s.frames_hint_contradicted);
  return text;
}

nlohmann::ordered_json RelocalizedJson(const loc::PoseEstimate& r,
                                       const loc::RelocalizerStatus* s) {
  nlohmann::ordered_json out = {
      {"stamp_s", r.stamp_s},
      {"x_m", r.T_map_base.x()},
      {"y_m", r.T_map_base.y()},
      {"yaw_deg", r.T_map_base.yaw() * 180.0 / std::numbers::pi},
      {"sigma_xy_m", std::sqrt(0.5 * (r.covariance(0, 0) + r.covariance(1, 1)))},
      {"junction_sightings", s ? s->seeds : 0}};
  if (s == nullptr) return out;
  out["evidence"] = {{"log_likelihood", s->best_log_likelihood},
                     {"runner_up_log_likelihood", FiniteOrNull(s->runner_up_log_likelihood)},
                     {"excluded_by_hint_lead", FiniteOrNull(s->excluded_lead)},
                     {"excluded_by_hint_log_odds", FiniteOrNull(s->excluded_log_odds)},
                     {"matched", s->best_matched},
                     {"observations", s->best_matched + s->best_unmatched},
                     {"hypotheses", s->hypotheses},
                     {"travel_since_seed_m", s->travel_since_seed_m}};
  return out;
}

core::Result<std::vector<StreamSpan>> StreamSpans(const fs::path& dir, const core::Dataset& dataset,
                                                  const core::DatasetStreamOptions& used) {
  std::vector<StreamSpan> spans;
  const core::DatasetManifest& m = dataset.manifest;
  if (!dataset.wheel_encoders.empty()) {
    spans.push_back({"wheel encoders", dataset.wheel_encoders.front().stamp_s,
                     dataset.wheel_encoders.back().stamp_s,
                     m.wheel_encoders ? 1.0 / m.wheel_encoders->rate_hz : 0.0});
  }
  if (used.frames && !dataset.images.empty()) {
    spans.push_back({"camera frames", dataset.images.front().stamp_s, dataset.images.back().stamp_s,
                     m.camera ? 1.0 / m.camera->rate_hz : 0.0});
  }
  if (used.scans && m.lidar) {
    core::DatasetStreamOptions scans_only;
    scans_only.wheels = false;
    scans_only.frames = false;
    core::Result<core::DatasetStreams> scans = core::DatasetStreams::Open(dir, dataset, scans_only);
    if (!scans.ok()) return scans.status();
    core::DatasetEvent event;
    StreamSpan span{"LiDAR scans", 0.0, 0.0, 1.0 / m.lidar->rate_hz};
    bool any = false;
    for (;;) {
      core::Result<bool> next = scans->Next(&event);
      if (!next.ok()) return next.status();
      if (!*next) break;
      if (!any) span.first_s = event.stamp_s;
      span.last_s = event.stamp_s;
      any = true;
    }
    if (any) spans.push_back(span);
  }
  return spans;
}

}  // namespace groundline::tools
