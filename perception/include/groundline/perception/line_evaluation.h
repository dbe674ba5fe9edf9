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
// true marking's kind (rates, errors, NEES), by the extracted line's kind (false positives) and,
// given the straight nuisances of the frame (a simulator's truth), by nuisance class: the false
// lines that lie along a nuisance of the class, and the rates of the true lines that a nuisance of
// the class crosses or touches. Not thread-safe (accumulates).
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

// A straight thing on the floor that is not a marking (a shadow's edge, a
// row of glare, a tire mark, a patch's seam) in base_link, from a simulator's
// nuisance truth: for evaluation only.
struct NuisanceLine {
  std::string cls;
  Eigen::Vector2d a_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d b_m = Eigen::Vector2d::Zero();
};

struct NuisanceGates {
  // A line lies along a nuisance when both of its ends are within
  // max_offset_m of the nuisance's line, the directions differ by at most
  // max_angle_rad and their extents overlap by min_overlap_m.
  double max_offset_m = 0.05;
  double max_angle_rad = 0.0872665;  // 5 deg
  double min_overlap_m = 0.05;
  // A nuisance touches a true line when its segment comes within this of the
  // true line's seen segment.
  double touch_m = 0.03;
};

// The class of the nuisance that `line` lies along (the one with the smallest
// mean offset of the line's ends), or "" when it lies along none.
std::string NuisanceAlong(const ExtractedLine& line, std::span<const NuisanceLine> nuisances,
                          const NuisanceGates& gates = {});

class LineEvaluation {
 public:
  // `nuisances`: the frame's straight nuisances when they are known (null:
  // unknown; an empty list: none in view).
  void AddFrame(std::span<const ExtractedLine> extracted, std::span<const TrueLine> truths,
                const LineMatches& matches, const std::vector<NuisanceLine>* nuisances = nullptr);

  const LineErrorSummary& overall() const { return overall_; }
  // Keyed by core::MarkingKindName (truth; "<kind>_edge" for the single
  // visible edge of a wide marking) for rates and errors, and by
  // LineKindName (extracted) for detections / false detections.
  const std::map<std::string, LineErrorSummary>& by_truth_kind() const { return by_truth_kind_; }
  const std::map<std::string, LineErrorSummary>& by_extracted_kind() const {
    return by_extracted_kind_;
  }
  // Keyed by nuisance class, over the frames whose nuisances are known:
  // false_detections are the false lines along a nuisance of the class
  // ("none": along no nuisance), evaluated and detected truths those that a
  // nuisance of the class touches; detections are every extracted line of
  // those frames (the denominator of each class's false share).
  const std::map<std::string, LineErrorSummary>& by_nuisance() const { return by_nuisance_; }

 private:
  LineErrorSummary overall_;
  std::map<std::string, LineErrorSummary> by_truth_kind_;
  std::map<std::string, LineErrorSummary> by_extracted_kind_;
  std::map<std::string, LineErrorSummary> by_nuisance_;
  int nuisance_frame_detections_ = 0;
};

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_LINE_EVALUATION_H_
