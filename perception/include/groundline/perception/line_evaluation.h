// Accumulates the rates and errors of extracted lines against ground truth
// over many frames (ground_truth_lines.h), for `groundline extract` and the
// extraction tests.
//
// Per frame: true lines that are `evaluated` count for the true-positive
// rate (detected when matched); every extracted line counts for the
// false-positive share (unmatched, or a duplicate of a matched truth);
// matched pairs with an evaluated truth give the errors
// r = LineError(extracted, truth) = (d rho [m], d alpha [rad]) in the extracted
// line's description and the normalized estimation error squared
// NEES = r^T C^-1 r (C: the extracted line's covariance), which for a consistent covariance follows
// chi-square with 2 degrees of freedom: 95 % of values inside [0.0506, 7.378]. Breakdowns: by the
// true marking's kind (rates, errors, NEES) and by the extracted line's kind (false positives). Not
// thread-safe (accumulates).
#ifndef GROUNDLINE_PERCEPTION_LINE_EVALUATION_H_
#define GROUNDLINE_PERCEPTION_LINE_EVALUATION_H_

#include <map>
#include <span>
#include <string>
#include <vector>

#include "groundline/perception/ground_truth_lines.h"
#include "groundline/perception/line_extractor.h"

namespace groundline::perception {

inline constexpr double kChiSquare2Lower95 = 0.0506356;  // 2.5 % quantile
inline constexpr double kChiSquare2Upper95 = 7.37776;    // 97.5 % quantile

struct LineErrorSummary {
  int evaluated_truths = 0;
  int detected_truths = 0;
  int detections = 0;  // extracted lines (for the false-positive share)
  int false_detections = 0;
  std::vector<double> abs_rho_error_m;
  std::vector<double> abs_alpha_error_rad;
  std::vector<double> nees;

  double Tpr() const;      // detected / evaluated, NaN when none
  double FpShare() const;  // false / detections, NaN when none
  double MedianAbsRhoErrorM() const;
  double MedianAbsAlphaErrorRad() const;
  double NeesInsideBandShare() const;  // of nees inside [kChiSquare2Lower95, kChiSquare2Upper95]
};

class LineEvaluation {
 public:
  void AddFrame(std::span<const ExtractedLine> extracted, std::span<const TrueLine> truths,
                const LineMatches& matches);

  const LineErrorSummary& overall() const { return overall_; }
  // Keyed by core::MarkingKindName (truth; "<kind>_edge" for the single
  // visible edge of a wide marking) for rates and errors, and by
  // LineKindName (extracted) for detections / false detections.
  const std::map<std::string, LineErrorSummary>& by_truth_kind() const { return by_truth_kind_; }
  const std::map<std::string, LineErrorSummary>& by_extracted_kind() const {
    return by_extracted_kind_;
  }

 private:
  LineErrorSummary overall_;
  std::map<std::string, LineErrorSummary> by_truth_kind_;
  std::map<std::string, LineErrorSummary> by_extracted_kind_;
};


}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_LINE_EVALUATION_H_
