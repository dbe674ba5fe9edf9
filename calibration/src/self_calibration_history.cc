#include "groundline/calibration/self_calibration_history.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "groundline/core/angles.h"
#include "groundline/core/json_fields.h"
#include "xml_text.h"

namespace groundline::calibration {
namespace {

struct Component {
  const char* title;
  const char* value_key;
  const char* sigma_key;
  const char* applied_key;   // the mount the BEV was made with
  const char* observed_key;  // the mount the lines were read under
  double to_display;        // field units -> the plot's (deg, mm)
  double from_field;        // field units -> the estimator's (rad, m)
  const char* unit;
};
// In MountComponent order. The health fields are degrees and metres.
constexpr Component kComponents[4] = {
    {"pitch", "selfcal_pitch_deg", "selfcal_pitch_sigma_deg", "selfcal_applied_pitch_deg",
     "selfcal_observed_pitch_deg", 1.0, core::kDegToRad, "deg"},
    {"roll", "selfcal_roll_deg", "selfcal_roll_sigma_deg", "selfcal_applied_roll_deg",
     "selfcal_observed_roll_deg", 1.0, core::kDegToRad, "deg"},
    {"height", "selfcal_height_m", "selfcal_height_sigma_m", "selfcal_applied_height_m",
     "selfcal_observed_height_m", 1000.0, 1.0, "mm"},
    {"yaw", "selfcal_yaw_deg", "selfcal_yaw_sigma_deg", "selfcal_applied_yaw_deg",
     "selfcal_observed_yaw_deg", 1.0, core::kDegToRad, "deg"},
};

MountVector TruthVector(const core::CameraExtrinsicsRecord& r) {
  return MountVector(r.pitch_rad, r.roll_rad, r.height_m, r.yaw_rad);
}

// The truth record in force at stamp_s (the last at or before it; the first
// for earlier stamps).
const core::CameraExtrinsicsRecord& TruthAt(const std::vector<core::CameraExtrinsicsRecord>& t,
                                            double stamp_s) {
  auto it = std::upper_bound(t.begin(), t.end(), stamp_s,
                             [](double s, const core::CameraExtrinsicsRecord& r) {
                               return s < r.stamp_s;
                             });
  return it == t.begin() ? t.front() : *std::prev(it);
}

std::string FormatNumber(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

}  // namespace

core::Result<std::vector<SelfCalibrationSample>> ReadSelfCalibrationHistory(
    const std::filesystem::path& health_jsonl) {
  std::ifstream in(health_jsonl);
  if (!in) return core::Status::Error(health_jsonl.string() + ": cannot open");
  std::vector<SelfCalibrationSample> out;
  std::string text;
  int line_number = 0;
  while (std::getline(in, text)) {
    ++line_number;
    if (text.empty()) continue;
    const std::string where = health_jsonl.string() + ":" + std::to_string(line_number);
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object())
      return core::Status::Error(where + ": expected one JSON object per line");
    if (!j.contains("selfcal_pitch_deg")) continue;
    core::JsonFieldReader r(where);
    SelfCalibrationSample s;
    s.stamp_s = r.Finite(j, "", "stamp_s");
    for (int i = 0; i < 4; ++i) {
      const Component& c = kComponents[i];
      s.value(i) = r.Finite(j, "", c.value_key) * c.from_field;
      s.sigma(i) = r.Finite(j, "", c.sigma_key) * c.from_field;
      if (r.ok() && s.sigma(i) < 0.0) r.Fail(c.sigma_key, "a sigma >= 0", std::to_string(s.sigma(i)));
    }
    if (const nlohmann::json* a = r.Get(j, "", "selfcal_alarm"); a != nullptr) {
      if (!a->is_boolean()) {
        r.Fail("selfcal_alarm", "true or false", a->dump());
      } else {
        s.alarm = a->get<bool>();
      }
    }
    if (j.contains("selfcal_applied_pitch_deg")) {
      MountVector applied;
      for (int i = 0; i < 4; ++i)
        applied(i) = r.Finite(j, "", kComponents[i].applied_key) * kComponents[i].from_field;
      s.applied = applied;
    }
    if (j.contains("selfcal_observed_pitch_deg")) {
      MountVector observed;
      for (int i = 0; i < 4; ++i)
        observed(i) = r.Finite(j, "", kComponents[i].observed_key) * kComponents[i].from_field;
      s.observed = observed;
    }
    if (s.alarm && j.contains("selfcal_alarm_message"))
      s.alarm_message = r.String(j, "", "selfcal_alarm_message");
    for (auto [key, count] :
         {std::pair{"selfcal_windows", &s.windows}, {"selfcal_steps", &s.steps}}) {
      const std::int64_t n = r.Id(j, "", key);
      if (r.ok() && (n < 0 || n > 1000000000)) {
        r.Fail(key, "a count in [0, 1e9]", std::to_string(n));
      }
      *count = static_cast<int>(r.ok() ? n : 0);
    }
    if (!r.ok()) return r.status();
    out.push_back(std::move(s));
  }
  if (out.empty()) {
    return core::Status::Error(health_jsonl.string() +
                               ": no selfcal_* fields: the run was not self-calibrated (run "
                               "localize with --self-calibrate)");
  }
  return out;
}

SelfCalibrationErrors CompareWithTruth(const std::vector<SelfCalibrationSample>& history,
                                       const std::vector<core::CameraExtrinsicsRecord>& truth,
                                       double from_s) {
  SelfCalibrationErrors e;
  if (truth.empty()) return e;
  MountVector sum_sq = MountVector::Zero(), inside = MountVector::Zero();
  for (const SelfCalibrationSample& s : history) {
    if (s.windows == 0 || s.stamp_s < from_s) continue;
    const MountVector error = s.value - TruthVector(TruthAt(truth, s.stamp_s));
    ++e.samples;
    for (int i = 0; i < 4; ++i) {
      e.max_abs(i) = std::max(e.max_abs(i), std::abs(error(i)));
      sum_sq(i) += error(i) * error(i);
      if (std::abs(error(i)) <= 3.0 * s.sigma(i)) inside(i) += 1.0;
    }
  }
  if (e.samples > 0) {
    e.rms = (sum_sq / e.samples).cwiseSqrt();
    e.within_3_sigma = inside / e.samples;
  }
  return e;
}

std::string SelfCalibrationHistoryHtml(const std::vector<SelfCalibrationSample>& history,
                                       const std::vector<core::CameraExtrinsicsRecord>* truth,
                                       const std::string& title) {
  constexpr int kWidth = 900, kHeight = 180, kLeft = 70, kRight = 20, kTop = 20, kBottom = 30;
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>"
    << internal::XmlEscape(title)
    << "</title><style>body{font-family:sans-serif;max-width:960px;margin:1em auto}"
       "svg{display:block;margin-bottom:0.5em}td,th{padding:2px 8px}</style></head><body>\n"
    << "<h1>" << internal::XmlEscape(title) << "</h1>\n";
  if (history.empty()) return h.str() + "<p>No samples.</p></body></html>\n";
  const double t0 = history.front().stamp_s, t1 = std::max(history.back().stamp_s, t0 + 1e-3);
  // The alarm's episodes: from the sample that raised it to the last that
  // kept it (the message of each, first and last: the estimate goes on).
  struct Episode {
    double raised_s, last_s;
    std::string first_message, last_message;
    bool standing;  // to the end of the run
  };
  std::vector<Episode> episodes;
  int alarms = 0;
  for (std::size_t i = 0; i < history.size(); ++i) {
    const SelfCalibrationSample& s = history[i];
    if (!s.alarm) continue;
    ++alarms;
    if (i == 0 || !history[i - 1].alarm) {
      episodes.push_back({s.stamp_s, s.stamp_s, s.alarm_message, s.alarm_message, false});
    }
    episodes.back().last_s = s.stamp_s;
    episodes.back().last_message = s.alarm_message;
    episodes.back().standing = i + 1 == history.size();
  }
  h << "<p>" << history.size() << " keyframes from " << FormatNumber("%.1f", t0) << " s to "
    << FormatNumber("%.1f", t1) << " s; " << history.back().windows << " windows fused, "
    << history.back().steps << " steps detected; ";
  if (episodes.empty()) {
    h << "no alarm";
  } else {
    h << "the alarm stood at " << alarms << " keyframes, raised first at "
      << FormatNumber("%.1f", episodes.front().raised_s) << " s";
  }
  h << ". Blue: the estimate, its 3-sigma band shaded; grey dashes: the commissioned "
       "mount (the estimate's start)";
  if (truth != nullptr && !truth->empty()) {
    h << "; black: the true mount of the simulation (evaluation only, not available on a "
         "vehicle)";
  }
  if (history.back().applied) h << "; green: the mount the bird's-eye view was made with";
  if (history.back().observed) h << "; orange: the mount the lines were read under";
  h << "; red marks: the alarm raised.</p>\n";
  for (int i = 0; i < 4; ++i) {
    const Component& c = kComponents[i];
    // The y range: estimates (after the first window), the mounts the BEV
    // was made with and the lines were read under (a suspected step's can
    // lie beyond every estimate), truth, and a band of at least 3 typical
    // sigmas.
    double lo = 1e300, hi = -1e300;
    const auto include = [&](double v) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    };
    std::vector<double> sigmas;
    for (const SelfCalibrationSample& s : history) {
      if (s.windows == 0) continue;
      include(MountComponentInUnit(i, s.value(i)));
      if (s.applied) include(MountComponentInUnit(i, (*s.applied)(i)));
      if (s.observed) include(MountComponentInUnit(i, (*s.observed)(i)));
      sigmas.push_back(MountComponentInUnit(i, s.sigma(i)));
    }
    if (truth != nullptr) {
      for (const core::CameraExtrinsicsRecord& r : *truth) {
        if (r.stamp_s < t0 || r.stamp_s > t1) continue;
        include(MountComponentInUnit(i, TruthVector(r)(i)));
      }
      include(MountComponentInUnit(i, TruthVector(TruthAt(*truth, t0))(i)));
    }
    const double commissioned = MountComponentInUnit(i, history.front().value(i));
    if (history.front().windows == 0) include(commissioned);
    if (lo > hi) lo = hi = commissioned;
    double typical = 0.0;
    if (!sigmas.empty()) {
      std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2, sigmas.end());
      typical = sigmas[sigmas.size() / 2];
    }
    const double pad = std::max({0.15 * (hi - lo), 4.0 * typical, i == kMountHeight ? 0.5 : 0.01});
    lo -= pad;
    hi += pad;
    const auto X = [&](double t) { return kLeft + (t - t0) / (t1 - t0) * (kWidth - kLeft - kRight); };
    const auto Y = [&](double v) {
      const double y = kTop + (hi - v) / (hi - lo) * (kHeight - kTop - kBottom);
      return std::clamp(y, static_cast<double>(kTop), static_cast<double>(kHeight - kBottom));
    };
    h << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kWidth << "' height='" << kHeight
      << "' font-size='12' data-component='" << c.title << "'>\n"
      << "<rect x='" << kLeft << "' y='" << kTop << "' width='" << kWidth - kLeft - kRight
      << "' height='" << kHeight - kTop - kBottom << "' fill='none' stroke='#888'/>\n"
      << "<text x='4' y='14' font-weight='bold'>" << c.title << " [" << c.unit << "]</text>\n";
    for (int k = 0; k <= 4; ++k) {
      const double v = lo + (hi - lo) * k / 4.0;
      h << "<text x='" << kLeft - 4 << "' y='" << FormatNumber("%.1f", Y(v) + 4)
        << "' text-anchor='end'>" << FormatNumber(i == kMountHeight ? "%.1f" : "%.3f", v) << "</text>\n";
      const double t = t0 + (t1 - t0) * k / 4.0;
      h << "<text x='" << FormatNumber("%.1f", X(t)) << "' y='" << kHeight - 8
        << "' text-anchor='middle'>" << FormatNumber("%.0f s", t) << "</text>\n";
    }
    // The band, then the estimate, over the samples with a window fused.
    std::ostringstream upper, lower, line;
    for (const SelfCalibrationSample& s : history) {
      if (s.windows == 0) continue;
      const double v = MountComponentInUnit(i, s.value(i)), d = 3.0 * MountComponentInUnit(i, s.sigma(i));
      upper << FormatNumber("%.1f", X(s.stamp_s)) << "," << FormatNumber("%.1f", Y(v + d)) << " ";
      line << FormatNumber("%.1f", X(s.stamp_s)) << "," << FormatNumber("%.1f", Y(v)) << " ";
    }
    for (auto it = history.rbegin(); it != history.rend(); ++it) {
      if (it->windows == 0) continue;
      const double v = MountComponentInUnit(i, it->value(i)), d = 3.0 * MountComponentInUnit(i, it->sigma(i));
      lower << FormatNumber("%.1f", X(it->stamp_s)) << "," << FormatNumber("%.1f", Y(v - d)) << " ";
    }
    h << "<polygon class='band' points='" << upper.str() << lower.str()
      << "' fill='#9ecae1' fill-opacity='0.5' stroke='none'/>\n";
    if (history.front().windows == 0) {
      h << "<line x1='" << kLeft << "' x2='" << kWidth - kRight << "' y1='"
        << FormatNumber("%.1f", Y(commissioned)) << "' y2='" << FormatNumber("%.1f", Y(commissioned))
        << "' stroke='#999' stroke-dasharray='6,4'/>\n";
    }
    if (truth != nullptr && !truth->empty()) {
      std::ostringstream steps;
      double previous = MountComponentInUnit(i, TruthVector(TruthAt(*truth, t0))(i));
      steps << FormatNumber("%.1f", X(t0)) << "," << FormatNumber("%.1f", Y(previous)) << " ";
      for (const core::CameraExtrinsicsRecord& r : *truth) {
        if (r.stamp_s <= t0 || r.stamp_s > t1) continue;
        const double v = MountComponentInUnit(i, TruthVector(r)(i));
        steps << FormatNumber("%.1f", X(r.stamp_s)) << "," << FormatNumber("%.1f", Y(previous)) << " "
              << FormatNumber("%.1f", X(r.stamp_s)) << "," << FormatNumber("%.1f", Y(v)) << " ";
        previous = v;
      }
      steps << FormatNumber("%.1f", X(t1)) << "," << FormatNumber("%.1f", Y(previous));
      h << "<polyline class='truth' points='" << steps.str()
        << "' fill='none' stroke='black' stroke-width='1.5'/>\n";
    }
    // A mount the run recorded beside the estimate, as a dashed line.
    const auto recorded = [&](std::optional<MountVector> SelfCalibrationSample::*mount,
                              const char* css_class, const char* stroke, const char* width,
                              const char* dashes) {
      std::ostringstream points;
      for (const SelfCalibrationSample& s : history) {
        if (!(s.*mount)) continue;
        points << FormatNumber("%.1f", X(s.stamp_s)) << ","
               << FormatNumber("%.1f", Y(MountComponentInUnit(i, (*(s.*mount))(i)))) << " ";
      }
      if (points.str().empty()) return;
      h << "<polyline class='" << css_class << "' points='" << points.str()
        << "' fill='none' stroke='" << stroke << "' stroke-width='" << width
        << "' stroke-dasharray='" << dashes << "'/>\n";
    };
    recorded(&SelfCalibrationSample::applied, "applied", "#31a354", "1.5", "4,2");
    recorded(&SelfCalibrationSample::observed, "observed", "#e6550d", "1.2", "2,2");
    h << "<polyline class='estimate' points='" << line.str()
      << "' fill='none' stroke='#2171b5' stroke-width='1.5'/>\n";
    for (const SelfCalibrationSample& s : history) {
      if (!s.alarm) continue;
      h << "<line class='alarm' x1='" << FormatNumber("%.1f", X(s.stamp_s)) << "' x2='"
        << FormatNumber("%.1f", X(s.stamp_s)) << "' y1='" << kHeight - kBottom << "' y2='"
        << kHeight - kBottom - 8 << "' stroke='red'/>\n";
    }
    h << "</svg>\n";
  }
  h << "<h2>Alarms</h2>\n";
  if (episodes.empty()) h << "<p>None.</p>\n";
  for (const Episode& e : episodes) {
    h << "<p class='alarm-message'>Raised at " << FormatNumber("%.1f s", e.raised_s)
      << (e.standing ? ", standing at the end of the run"
                     : ", last at " + FormatNumber("%.1f s", e.last_s))
      << ": " << internal::XmlEscape(e.first_message);
    if (e.last_message != e.first_message) {
      h << "<br>At " << FormatNumber("%.1f s", e.last_s) << ": "
        << internal::XmlEscape(e.last_message);
    }
    h << "</p>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

}  // namespace groundline::calibration
