// Rates and errors of extracted lines (line_evaluation.h).
#include "groundline/perception/line_evaluation.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

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
double LineErrorSummary::MedianAbsAlphaErrorRad() const { return core::Median(abs_alpha_error_rad); }
double LineErrorSummary::NeesInsideBandShare() const {
  const auto inside = std::count_if(nees.begin(), nees.end(), [](double e) {
    return e >= kChiSquare2Lower95 && e <= kChiSquare2Upper95;
  });
  return Ratio(static_cast<int>(inside), static_cast<int>(nees.size()));
}

void LineEvaluation::AddFrame(std::span<const ExtractedLine> extracted,
                              std::span<const TrueLine> truths, const LineMatches& matches) {
  for (size_t j = 0; j < truths.size(); ++j) {
    if (!truths[j].evaluated) continue;
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
  }
}

}  // namespace groundline::perception
