// Rates and errors of extracted lines (line_evaluation.h).
#include "groundline/perception/line_evaluation.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "groundline/core/segment_distance.h"
#include "groundline/core/statistics.h"

namespace groundline::perception {

namespace {
double Ratio(int a, int b) {
  return b > 0 ? static_cast<double>(a) / b : std::numeric_limits<double>::quiet_NaN();
}
}  // namespace

double LineErrorSummary::Tpr() const { return Ratio(detected_truths, evaluated_truths); }
double LineErrorSummary::FpShare() const { return Ratio(false_detections, detections); }
double LineErrorSummary::MedianAbsRhoErrorM() const { return core::Median(abs_rho_error_m); }
double LineErrorSummary::MedianAbsAlphaErrorRad() const {
  return core::Median(abs_alpha_error_rad);
}
double LineErrorSummary::NeesInsideBandShare() const {
  const auto inside = std::count_if(nees.begin(), nees.end(), [](double e) {
    return e >= kChiSquare2Lower95 && e <= kChiSquare2Upper95;
  });
  return Ratio(static_cast<int>(inside), static_cast<int>(nees.size()));
}

std::string NuisanceAlong(const ExtractedLine& line, std::span<const NuisanceLine> nuisances,
                          const NuisanceGates& gates) {
  const Eigen::Vector2d d = line.end_m - line.start_m;
  const double length = d.norm();
  if (length <= 0.0) return {};
  const Eigen::Vector2d u = d / length;
  std::string best;
  double best_offset = gates.max_offset_m;
  for (const NuisanceLine& n : nuisances) {
    const Eigen::Vector2d e = n.b_m - n.a_m;
    const double n_length = e.norm();
    if (n_length <= 0.0) continue;
    const Eigen::Vector2d v = e / n_length;
    if (std::abs(u.x() * v.y() - u.y() * v.x()) > std::sin(gates.max_angle_rad)) continue;
    const auto offset = [&](const Eigen::Vector2d& p) {
      const Eigen::Vector2d w = p - n.a_m;
      return std::abs(v.x() * w.y() - v.y() * w.x());
    };
    const double mean_offset = 0.5 * (offset(line.start_m) + offset(line.end_m));
    if (std::max(offset(line.start_m), offset(line.end_m)) > gates.max_offset_m ||
        mean_offset > best_offset) {
      continue;
    }
    // Overlap of the two extents along the nuisance.
    const double s0 = (line.start_m - n.a_m).dot(v), s1 = (line.end_m - n.a_m).dot(v);
    const double overlap = std::min(std::max(s0, s1), n_length) - std::max(std::min(s0, s1), 0.0);
    if (overlap < gates.min_overlap_m) continue;
    best = n.cls;
    best_offset = mean_offset;
  }
  return best;
}

void LineEvaluation::AddFrame(std::span<const ExtractedLine> extracted,
                              std::span<const TrueLine> truths, const LineMatches& matches,
                              const std::vector<NuisanceLine>* nuisances) {
  const NuisanceGates gates;
  if (nuisances) {
    nuisance_frame_detections_ += static_cast<int>(extracted.size());
    by_nuisance_["none"];  // present whenever nuisances are known
    for (auto& [cls, s] : by_nuisance_) s.detections = nuisance_frame_detections_;
  }
  for (size_t j = 0; j < truths.size(); ++j) {
    if (!truths[j].evaluated) continue;
    // The nuisance classes that touch this true line.
    std::set<std::string> touching;
    for (const NuisanceLine& n : nuisances ? *nuisances : std::vector<NuisanceLine>{}) {
      if (core::SegmentSegmentDistance(truths[j].start_m, truths[j].end_m, n.a_m, n.b_m) <=
          gates.touch_m) {
        touching.insert(n.cls);
      }
    }
    const bool touched_detected = matches.extracted_of_truth[j] >= 0;
    for (const std::string& cls : touching) {
      LineErrorSummary& s = by_nuisance_[cls];
      s.detections = nuisance_frame_detections_;
      ++s.evaluated_truths;
      if (touched_detected) ++s.detected_truths;
    }
    std::string key(core::MarkingKindName(truths[j].kind));
    if (truths[j].edge != 0) key += "_edge";
    LineErrorSummary& kind = by_truth_kind_[key];
    const bool detected = matches.extracted_of_truth[j] >= 0;
    for (LineErrorSummary* s : {&overall_, &kind}) {
      ++s->evaluated_truths;
      if (detected) ++s->detected_truths;
    }
    if (!detected) continue;
    const ExtractedLine& line = extracted[matches.extracted_of_truth[j]];
    const Eigen::Vector2d r = LineError(line.line, truths[j].line);
    const double nees = r.dot(line.covariance.inverse() * r);
    for (LineErrorSummary* s : {&overall_, &kind}) {
      s->abs_rho_error_m.push_back(std::abs(r(0)));
      s->abs_alpha_error_rad.push_back(std::abs(r(1)));
      s->nees.push_back(nees);
    }
  }
  for (size_t i = 0; i < extracted.size(); ++i) {
    LineErrorSummary& kind = by_extracted_kind_[std::string(LineKindName(extracted[i].kind))];
    const bool false_detection = matches.truth_of_extracted[i] < 0;
    for (LineErrorSummary* s : {&overall_, &kind}) {
      ++s->detections;
      if (false_detection) ++s->false_detections;
    }
    if (nuisances && false_detection) {
      const std::string cls = NuisanceAlong(extracted[i], *nuisances, gates);
      LineErrorSummary& s = by_nuisance_[cls.empty() ? "none" : cls];
      s.detections = nuisance_frame_detections_;
      ++s.false_detections;
    }
  }
}

}  // namespace groundline::perception
