// Ground truth for line extraction: which floor-map markings a camera frame
// sees, as Hesse lines in base_link, and the matching of extracted lines to
// them (the rates and errors of `groundline extract`).
//
// Visible lines. For a frame taken at the vehicle's true pose T_map_base, each
// straight piece of a marking's centre-line polyline (core/floor_map.h) is
// transformed into base_link, sampled every sample_step_m, and clipped to the
// footprint (a predicate on base_link points: the part of the floor where the
// extractor can find lines) and, for dashed tape, to the dashes (the pattern
// starts with a dash at the first vertex, along the arc length). With
// tape_occludes_joints, a sample of a dark marking (a joint) that lies under
// a bright marking's paint (within its half width, on a dash) is not seen:
// the tape covers the groove, and the extractor reports tape and groove there
// as the one tape line (LineExtractorOptions::same_marking_distance_m); the
// joint counts only where it runs between dashes or beside the tape. A piece with
// any seen sample is a TrueLine; it is `evaluated` when at least
// min_evaluated_length_m of it lies eval_x_min_m..eval_x_max_m ahead, with
// one unbroken run of at least min_evaluated_run_m there. Wear is
// not in the map, so a fully worn marking still counts.
//
// Wide markings (width_m >= edge_min_width_m: stop bars, crosswalk stripes)
// are seen as two step edges; the extractor reports their centre line where it
// sees both edges over at least half of the longer one, else the longer edge
// itself when it is seen over at least edge_min_seen_length_m (a shorter
// bright edge cannot be told from the end of a bar). So a wide piece gives up
// to three TrueLines: the centre line over the samples where both edges
// (centre +- width / 2 across) are in the footprint, and each edge line
// (edge = +1: left of the polyline's direction, -1: right) over the samples
// where that edge is in the footprint. Only the one the extractor should
// report can be evaluated; the others may still be matched (no false
// positive) but do not count.
//
// Matching. An extracted line matches a true one when LineDifference(extracted,
// true) is within the gates (|d rho| <= rho_gate_m, |d alpha| <= alpha_gate_rad)
// and their extents along the true line overlap by at least min_overlap_m.
// Each extracted line takes the closest gated true line (Mahalanobis-free: by
// |d rho| / rho_gate + |d alpha| / alpha_gate); a true line matched by several
// extracted lines keeps the closest, the others count as unmatched
// (duplicates). Pure and thread-safe.
#ifndef GROUNDLINE_PERCEPTION_GROUND_TRUTH_LINES_H_
#define GROUNDLINE_PERCEPTION_GROUND_TRUTH_LINES_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "groundline/core/floor_map.h"
#include "groundline/core/se2.h"
#include "groundline/perception/hesse_line.h"
#include "groundline/perception/junctions.h"

namespace groundline::perception {

struct VisibleLineOptions {
  double sample_step_m = 0.01;
  double eval_x_min_m = 1.0;  // the range ahead where errors and rates count
  double eval_x_max_m = 2.5;
  double min_evaluated_length_m = 0.30;
  // .. of which one run without unseen samples is at least this long: the
  // extractor's least line (LineExtractorOptions::min_line_length_m; a piece
  // that only grazes the footprint's border, seen at scattered cells, or
  // seen in short bits between dashes, is no line it can find). 0: off.
  double min_evaluated_run_m = 0.20;
  double edge_min_width_m = 0.12;       // wide markings: seen as two edges (see above)
  double edge_min_seen_length_m = 0.6;  // LineExtractorOptions::single_edge_min_length_m
  bool tape_occludes_joints = true;     // false: the definition before issue 4's audit
  double occlusion_reach_m = 4.0;       // bright markings farther from base_link are ignored
};

struct TrueLine {
  std::int64_t marking_id = 0;
  int piece = 0;  // index of the polyline piece
  core::MarkingKind kind = core::MarkingKind::kTapeSolid;
  core::MarkingPolarity polarity = core::MarkingPolarity::kBright;
  int edge = 0;    // 0: the centre line; +1 / -1: the left / right edge of a wide marking
  HesseLine line;  // base_link
  Eigen::Vector2d start_m = Eigen::Vector2d::Zero();  // first and last seen sample, base_link
  Eigen::Vector2d end_m = Eigen::Vector2d::Zero();
  double seen_length_m = 0.0;            // in the footprint (and on dashes)
  double evaluated_length_m = 0.0;       // of that, eval_x_min_m..eval_x_max_m ahead
  double longest_evaluated_run_m = 0.0;  // the longest run of consecutive such samples
  bool evaluated = false;
};

using FootprintPredicate = std::function<bool(const Eigen::Vector2d& point_base_m)>;

std::vector<TrueLine> VisibleMarkingLines(const core::FloorMap& map, const core::SE2& T_map_base,
                                          const FootprintPredicate& footprint,
                                          const VisibleLineOptions& options);

struct MatchGates {
  double rho_gate_m = 0.05;
  double alpha_gate_rad = 0.0349066;  // 2 deg
  double min_overlap_m = 0.05;
};

struct LineMatches {
  std::vector<int> truth_of_extracted;  // index into truths, -1: unmatched
  std::vector<int> extracted_of_truth;  // index into extracted, -1: missed
};

// extracted_polarity: empty, or one per extracted line; then an extracted
// line matches only true lines of its polarity (a bright line beside a joint
// is not that joint).
LineMatches MatchLines(std::span<const LineSegmentEstimate> extracted,
                       std::span<const TrueLine> truths, const MatchGates& gates,
                       std::span<const core::MarkingPolarity> extracted_polarity = {});

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_GROUND_TRUTH_LINES_H_
