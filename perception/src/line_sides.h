// Private to the line extractor: the side-contrast test on the BEV, the
// pairing of wide-bar edges into centre lines (line_sides.cc), side-lobe
// removal and the merging of one marking's lines (line_merging.cc).
#ifndef GROUNDLINE_PERCEPTION_SRC_LINE_SIDES_H_
#define GROUNDLINE_PERCEPTION_SRC_LINE_SIDES_H_

#include <Eigen/Core>
#include <limits>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

#include "groundline/perception/bev_remap.h"
#include "groundline/perception/line_extractor.h"

namespace groundline::perception::internal {

// A fitted line before the side test, with its floor centres.
// Straightness: the centres' deviation across a line fitted by a parabola in
// the position along it (y = a + b t + c t^2, t centred): the parabola's
// sagitta over the centres' span, |c| (L / 2)^2, metres, and its standard
// deviation from the residuals about the parabola. A straight marking gives
// a sagitta within its noise; an arc of radius R over a length L gives
// L^2 / (8 R).
struct Sagitta {
  double sagitta_m = 0.0;
  double sigma_m = 0.0;
  double span_m = 0.0;  // of the centres along the line
};
// correlation_samples: how many neighbouring centres share one centre's error
// (LineExtractorOptions::CorrelationSamples).
Sagitta MeasureSagitta(const HesseLine& line, const std::vector<Eigen::Vector2d>& points_m,
                       double correlation_samples);

struct CandidateLine {
  ExtractedLine line;
  std::vector<Eigen::Vector2d> centres_m;
  // Mean BEV grey level at the centres minus at side_offset along +n and -n
  // (n: the line's normal in base_link).
  double contrast_plus = 0.0;
  double contrast_minus = 0.0;
  double centre_grey = 0.0;  // mean BEV grey level at the centres
  // The share of centres where the line is a narrow ridge of its polarity
  // (MeasureSideContrast).
  double narrow_share = 0.0;
  Sagitta sagitta;  // MeasureSagitta of the centres about the line
};



// Fills contrast_plus / contrast_minus / centre_grey from the BEV (CV_32FC1),
// and narrow_share: the share of the centres (seen with both sides) whose
// local contrast against each side (offset_m away) is >= min_local_contrast
// and whose grey level near_offset_m to each side has recovered at least
// half of the way from the centre to that side. The line's polarity must be
// set.
void MeasureSideContrast(const cv::Mat& bev_float, const BevGrid& grid, double offset_m,
                         double near_offset_m, double min_local_contrast, CandidateLine* candidate);

// The kept lines of one polarity: lines brighter (bright) or darker (dark)
// than both sides by min_contrast; for bright, also the centre lines of
// facing edge pairs (see line_extractor.h). Bright lines and the edges of a
// bar must have sharp flanks (MeasureFlankSharpness >=
// options.min_flank_sharpness): a glare band's are Gaussian. Bright lines must also be
// brighter than the frame's median floor grey level by min_side_contrast
// (concrete between two dark scuffs or oil stains is a ridge, but no tape).
// A pair of facing edges is a bar only when the floor between them is not
// rougher, in grey levels, than the floor outside (paint;
// options.bar_min_roughness_ratio, MeasureSideRoughness on the BEV,
// CV_32FC1): lit concrete between two shadows is no bar.
// Appends to *out; bright edges without a facing partner go to
// *unpaired_edges if not null.
void SelectLines(std::vector<CandidateLine> candidates, LinePolarity polarity,
                 double floor_median_grey, const cv::Mat& bev_float, const BevGrid& grid,
                 const LineExtractorOptions& options, std::vector<ExtractedLine>* out,
                 std::vector<CandidateLine>* unpaired_edges = nullptr);

// The step edge next to a one-sided bright ridge (the inner flank of a wide
// bar whose other edge is unseen): from each ridge centre the BEV (CV_32FC1)
// is sampled every cell toward the dark side (the side of the larger
// contrast), -2..14 cells; the steepest bright-to-dark central difference,
// refined by a parabola through it and its neighbours, is the edge point.
// Points whose steepest step is smaller than min_step_dn grey levels per 2
// cells, at the ends of the profile, whose far side does not stay darker than
// halfway for 2-6 cells beyond the edge (a groove, not a step), or off the
// seen floor are skipped.
// Floor points in base_link, in the order of the centres.
std::vector<Eigen::Vector2d> LocateBarEdge(const cv::Mat& bev_float, const BevGrid& grid,
                                           const CandidateLine& candidate, double min_step_dn);

// The share of edge points (base_link) from which the bright side stays
// bright until it leaves search_mask (CV_8U) within max_width_m: the bar goes
// on out of view. Its other edge in view (a fall to halfway to the dark side)
// or bright floor wider than any bar (concrete next to a dark object) does
// not count.
double OpenBrightSideShare(const cv::Mat& bev_float, const cv::Mat& search_mask,
                           const BevGrid& grid, const CandidateLine& candidate,
                           const std::vector<Eigen::Vector2d>& edge_points_m, double max_width_m);

// Relative roughness of the floor on either side of a bar's edge: over bands
// near_m..far_m from the edge points (base_link) into each side, the median
// absolute difference between neighbouring cells along the edge, divided by
// the side's median grey. Paint is smooth (its roughness is the sensor's
// noise); concrete is textured, and stays so in a shadow, whose light scales
// texture and grey alike. {bright side, dark side}; {0, 0} without samples.
// The same medians in grey levels (not divided by the grey): *_dn.
struct SideRoughness {
  double bright = 0.0;
  double dark = 0.0;
  double bright_dn = 0.0;
  double dark_dn = 0.0;
};
SideRoughness MeasureSideRoughness(const cv::Mat& bev_float, const BevGrid& grid,
                                   const CandidateLine& candidate,
                                   const std::vector<Eigen::Vector2d>& edge_points_m, double near_m,
                                   double far_m);

// How sharp a bright line's flanks are: per centre, the BEV (CV_32FC1) is
// sampled every cell along the normal out to max_cells (>= 2) on each darker
// side (both sides for a ridge, the side of the larger contrast for an
// edge); the steepest fall over two cells (a central difference, per cell)
// divided by the whole fall, from the brightest of the centre's cell and its
// neighbours to the mean of the side's outer half.
// A paint edge falls within a cell or two (about 0.35-0.5 per cell, less with
// motion blur across it); the Gaussian flank of a glare band of sigma s cells
// about 0.6 / s. The median over the centres whose every measured side falls
// by at least min_fall_dn; NaN when none.
double MeasureFlankSharpness(const cv::Mat& bev_float, const BevGrid& grid,
                             const CandidateLine& candidate, bool both_sides, int max_cells,
                             double min_fall_dn);

// How a line's band widens with its range from the camera's foot point
// foot_m (base_link): every 2 cm along the line (start_m to end_m) the BEV
// (CV_32FC1) is sampled across it, every cell out to max_half_width_m on each
// side; the band's edges are where the profile first crosses halfway from the
// centre (the brightest, for a dark line the darkest, of the centre's cell
// and its neighbours) to that side's level (the median of its outer third),
// and the width is the distance between them. With the median range and
// width of the nearer (rn, wn) and the farther half (rf, wf) of the positions
// measured: relative = (wf / wn - 1) / (rf / rn - 1), about 1 for a wedge with
// its apex at the foot point (a post's two vertical edges, both on rays),
// about 0 for a band of constant width (tape); increase_m = wf - wn. NaN when
// fewer than 8 positions are measured or rf - rn < 0.1 rn.
struct WidthGrowth {
  double relative = std::numeric_limits<double>::quiet_NaN();
  double increase_m = std::numeric_limits<double>::quiet_NaN();
};
WidthGrowth WidthGrowthWithRange(const cv::Mat& bev_float, const BevGrid& grid,
                                 const ExtractedLine& line, const Eigen::Vector2d& foot_m,
                                 double max_half_width_m);

// The median grey level of the BEV (CV_8U) over mask.
double MedianGrey(const cv::Mat& bev, const cv::Mat& mask);

// Sets merged's endpoints to the span of a's and b's endpoints projected
// onto merged's line (merged may alias a or b).
void SpanEndpoints(const ExtractedLine& a, const ExtractedLine& b, ExtractedLine* merged);

// The overlap of two lines' extents along a's direction, metres (< 0: a gap).
double Overlap(const ExtractedLine& a, const ExtractedLine& b);

// The ridge filter's response to a dark line has bright side lobes about
// sqrt(3) sigma to either side: bright lines (not bars) within max_distance_m
// and max_angle_rad of a dark line, overlapping it over half their length,
// are dropped.
void DropSideLobes(double max_distance_m, double max_angle_rad, std::vector<ExtractedLine>* lines);

// Lines of one polarity and kind of construction (ridge, bar centre, single
// edge) are one marking when their angles differ by <= max_angle_rad, both
// endpoints of the shorter lie within max_distance_m of the longer's line and
// they overlap over half of the shorter one (or are pieces of one line
// interrupted by a crossing marking: within 1 cm and 1 deg, any overlap).
// Pieces (the same ridge sampled from two Hough segments) keep the line with
// more samples, spanning both. Other groups (two ridges of one marking: a
// tape split by a joint under it, a biased second ridge) become the
// samples-weighted mean of (rho, alpha) (LineDifference) with the
// samples-weighted mean of their covariances (their errors are shared: no
// reduction), spanning all. Processes the lines with the most samples first.
inline constexpr double kDuplicateRhoM = 0.01;
inline constexpr double kDuplicateAlphaRad = 0.0175;
void MergeSameMarkingLines(double max_distance_m, double max_angle_rad,
                           std::vector<ExtractedLine>* lines);

}  // namespace groundline::perception::internal

#endif  // GROUNDLINE_PERCEPTION_SRC_LINE_SIDES_H_
