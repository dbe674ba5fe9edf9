// Floor lines from one BEV image (bev_remap.h): the whole per-frame pipeline
// of perception, in base_link.
//
//  1. Steerable ridge filter (steerable_ridge.h): Hessian, bright and dark
//     ridge energy, normal angle, eigen_ratio. Cells within
//     border_erosion_sigmas * sigma of the unseen area are ignored (the
//     filter there reaches far into cells the camera does not see, which
//     BevRemap fills from the nearest seen cell).
//  2. Per polarity: Otsu threshold of the energy, ridge centres by
//     non-maximum suppression, cv::HoughLinesP, collinear merging
//     (ridge_segments.h).
//  3. Sub-pixel ridge centres along each merged segment by parabolic peak
//     interpolation (ridge_refinement.h), outliers removed, and a weighted
//     total-least-squares fit in metric base_link coordinates whose
//     covariance comes from pixel noise through the back-projection Jacobian
//     of each centre (line_covariance.h).
//  4. Side contrast on the BEV: a line is a line when its centre is brighter
//     (bright) or darker (dark) than both sides at side_offset_cells; a bright
//     ridge that is brighter on one side only is the edge of a wide bar (a
//     stop bar, a crosswalk stripe), and two such edges facing each other are
//     replaced by their centre line; a bright edge without a partner (the
//     other edge of the bar is out of view) is located on the BEV as the
//     steepest step next to its ridge and becomes the line of that edge
//     (single_bar_edge); dark one-sided ridges are the flanks of bright bars
//     and are dropped. A bright line must also be brighter than
//     the frame's median floor grey (not just concrete between dark scuffs).
//  5. Rejection of glare and scuffs: anisotropy (eigen_ratio), the minimum
//     length, the support (fraction of positions along the segment with an
//     accepted centre) and the consistency of the ridge width along the line.
//  6. Classification (line_classification.h) and junctions (junctions.h).
//
// Thread-safety: a LineExtractor is immutable after construction; Extract is
// const and may run concurrently.
#ifndef GROUNDLINE_PERCEPTION_LINE_EXTRACTOR_H_
#define GROUNDLINE_PERCEPTION_LINE_EXTRACTOR_H_

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "groundline/calibration/bev_uncertainty.h"
#include "groundline/calibration/floor_projection.h"
#include "groundline/core/status.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/hesse_line.h"
#include "groundline/perception/junctions.h"
#include "groundline/perception/line_classification.h"
#include "groundline/perception/line_covariance.h"
#include "groundline/perception/ridge_refinement.h"
#include "groundline/perception/ridge_segments.h"
#include "groundline/perception/steerable_ridge.h"

namespace groundline::perception {

struct LineExtractorOptions {
  SteerableRidgeOptions ridge;
  RidgeSegmentOptions segments;
  RidgeRefinementOptions refinement;
  JunctionOptions junctions;
  bool bright = true;  // look for bright lines (tape)
  bool dark = true;    // look for dark lines (joints)
  // Exposure: the grey-level thresholds below are for a floor whose median
  // grey in the BEV is about this (the reference camera's exposure). A darker
  // frame (dim light, an exposure set for brighter floor, dark concrete) is
  // scaled up to it before extraction, so that a joint 40 % darker than its
  // floor is found at grey 30 as at grey 75. Brighter frames are left as they
  // are. 0: off.
  double reference_floor_grey = 75.0;
  // The dark energy threshold is clamped to at most this (<= 0:
  // segments.max_energy): an 8 mm joint's energy at sigma 3.5 cells is low,
  // and where an oil stain's edges lift the frame's Otsu threshold the joint
  // through the stain falls below it. Scuffs and stain edges that pass are
  // rejected by the narrowness, straightness and side tests. 5 -> 4 found
  // 13 more zone A joint pieces (seeds 2, 3; seed 1 unchanged) and added no
  // false positive on any of the 12 simulator datasets.
  double dark_max_energy = 4.0;
  // 0.5 with BevRemap's fill_unseen (the filter sees floor beyond the
  // border); 2.5 was needed while unseen cells were black (a step edge).
  // On the simulator datasets, 2.5 -> 0.5 took TPR A 0.948 -> 0.966, B 0.985
  // -> 1.000 (markings 1-4 cm inside the old border: the flank ridge of a
  // stop bar's near edge, transverse joints at the far edge).
  double border_erosion_sigmas = 0.5;
  // Refinement accepts centres down to this fraction of the frame's threshold.
  double sample_energy_fraction = 0.5;
  double outlier_cells = 1.5;  // centres farther than this from the first fit are dropped
  double min_line_length_m = 0.2;
  double min_support = 0.3;           // accepted centres / positions along the segment
  double max_width_variation = 0.35;  // std / mean of the peak width along the line
  // Centres whose peak width differs from the line's median by more than this
  // fraction of it belong to something crossing or overlapping the line (a
  // transverse joint, an oil stain over a joint, a dash's end) and are
  // dropped before the support and width tests.
  double width_outlier_fraction = 0.5;
  // Dark lines: centres where the floor side_offset_cells to either side
  // differs by more than this fraction of the line's depth there (centre
  // minus the sides' mean) lie against a lopsided floor, an oil stain or a
  // scuff on one side of the joint, which pulls the ridge toward it and may
  // bend the Hough segment off the joint. They are dropped with the width
  // outliers (zone C joints: TPR 0.992 -> 1.000, FP 1.2 -> 1.0 %; 0.5 gave
  // 0.997). Bright lines keep theirs: the flank ridge of a bar edge is
  // one-sided by nature. <= 0: off.
  double max_side_asymmetry = 0.3;
  double side_offset_cells = 7.0;
  double min_side_contrast = 3.0;        // grey levels of the BEV, bright lines
  // A narrow bright line is darker on both sides: its weaker side contrast
  // (the best over offsets up to side_offset_cells) is at least
  // min_bright_side_ratio of its stronger one, or at least
  // bright_side_min_grey_share of its own grey. Otherwise it is taken as an
  // edge, for the bar and single-edge tests: the lit flank of a shadow or a
  // stain is much brighter than its dark side only, and its other side is the
  // same lit floor, a few percent off its grey.
  double min_bright_side_ratio = 0.35;
  double bright_side_min_grey_share = 0.15;
  double min_bright_excess = 10.0;       // bright line centre over the frame's median grey
  double min_dark_side_contrast = 16.0;  // dark lines (joints are darker than scuffs)
  // A joint is a thin groove (8 mm + blur): at a centre, the grey level
  // dark_narrow_offset_cells to either side has recovered at least half of
  // the way to the side level (side_offset_cells away), with a local depth
  // of at least half min_dark_side_contrast; this must hold at
  // min_dark_narrow_share of the centres. Tire scuffs (2-4 cm, soft edges),
  // oil stains (>= 5 cm) and a stain's edge beside a joint are wider or
  // one-sided (docs/perception.md).
  double dark_narrow_offset_cells = 2.0;
  double min_dark_narrow_share = 0.7;
  // A joint is straight: its centres' sagitta (a parabola fitted across the
  // line, over its span) is at most this. Scuffs are arcs of 1-4 m radius
  // (0.6 m of a 2 m arc: 22 mm); true joints and tapes measured <= 11 mm
  // (simulator, seeds 1-3).
  double max_dark_sagitta_m = 0.012;
  // .. and not an arc: a sagitta over dark_min_significant_sagitta_m and over
  // dark_sagitta_significance of its own standard deviation (from the
  // centres' scatter about the parabola) whose radius is under
  // dark_arc_max_radius_m is a tire's scuff. A saw cut is straight on the
  // floor; the lens model's residual error bends it in the BEV into an arc of
  // tens of metres (up to 5 mm over 1.4 m), which passes.
  double dark_sagitta_significance = 3.0;
  double dark_min_significant_sagitta_m = 0.0015;
  double dark_arc_max_radius_m = 8.0;
  // A dark line shorter than dark_short_length_m whose centres scatter about
  // it by more than dark_short_max_rms_m (RMS) is dropped: a saw cut is
  // straight to the ridge's noise, a piece of scuff or stain edge is ragged.
  double dark_short_length_m = 0.5;
  double dark_short_max_rms_m = 0.0015;
  double bar_min_width_m = 0.08;     // two facing edges of a wide bar this far apart ..
  double bar_max_width_m = 0.70;     // .. up to this ..
  double bar_max_angle_rad = 0.035;  // .. and parallel within this
  // A bright edge without a facing partner (a bar whose other edge is out of
  // view) becomes the line of its step edge when its contrast (the larger
  // side contrast, and the steepest step per 2 cells) is at least this.
  // Its edge points must run without a gap longer than single_edge_max_gap_m
  // over at least single_edge_min_length_m (longer than a bar is wide: the
  // end of a bar is no such line).
  bool single_bar_edges = true;
  double single_edge_min_contrast = 10.0;  // grey levels
  double single_edge_max_gap_m = 0.1;
  double single_edge_min_length_m = 0.6;
  // Edge points are also looked for this far beyond the ends of the ridge
  // (within the search footprint): the one-sided ridge 3-4 cm inside a bar
  // fades near the bar's corners and the footprint's border before the edge
  // ends (a 71 cm edge had ridge centres over 56 cm only).
  double single_edge_extension_m = 0.12;
  // A bright edge whose dark side is darker than its bright side by this
  // fraction of the bright grey is kept even where the frame's median floor
  // grey is that of the markings filling most of the view.
  double single_edge_min_relative_contrast = 0.5;
  // A bar's bright side is paint, smoother than the floor beside it; the lit
  // side of a shadow's edge is the same concrete as its dark side, as rough
  // relative to its grey (internal::MeasureSideRoughness over bands
  // single_edge_roughness_near_m..far_m from the edge). The dark side must be
  // at least this many times rougher than the bright side. Paint beside
  // textured concrete: several times; on a smooth floor, where noise alone
  // makes the roughness, about the ratio of the greys (2 or more); a shadow's
  // edge: 1 to 1.5 (its dark side's sensor noise is relatively larger).
  double single_edge_min_roughness_ratio = 1.6;
  // A single edge that runs along a ray from the camera's foot point (the
  // angle between the edge and the ray to its midpoint at most this) is the
  // vertical edge of a thing standing on the floor (a box, a pallet, a wall,
  // a rack upright): the bird's-eye view smears such an edge along that ray.
  // A bar's edge lies on a ray only when the vehicle drives exactly along it
  // with the camera above it. Needs the camera's foot point (given by the
  // remap's mount). 0 turns the test off.
  double single_edge_max_radial_deg = 2.0;
  // A bright line near a ray from the camera's foot point (within
  // ray_line_max_angle_deg, as for single edges) whose band widens in
  // proportion to its range from the foot point (internal::
  // WidthGrowthWithRange above ray_line_max_width_growth, the band measured
  // out to ray_line_half_width_m to each side) is a thin thing standing on
  // the floor (a post, a leg, an upright): its two vertical edges both lie on
  // rays, a wedge with its apex at the foot point, where a tape keeps its
  // width. (A dark post wider than a joint fails the dark lines' narrowness
  // test already.) The band must also gain at least ray_line_min_width_increase_m
  // from its nearer half to its farther half: the bird's-eye view blurs with
  // the range (each pixel covers more floor), which widens a joint or a tape
  // by a few millimetres, in proportion too. A wider angle than for single edges: the width
  // decides, and a mount from a homography puts the foot point a little off. 0 turns it off.
  double ray_line_max_angle_deg = 5.0;
  double ray_line_max_width_growth = 0.5;
  double ray_line_min_width_increase_m = 0.015;
  double ray_line_half_width_m = 0.2;
  double single_edge_roughness_near_m = 0.03;
  double single_edge_roughness_far_m = 0.08;
  // For two facing edges (a bar's centre line) the roughness in grey levels,
  // not relative to the grey: the floor outside must be at least this many
  // times as rough as the floor between them (the same bands, the inner one
  // cut short of the other edge). Paint is smoother than concrete in grey
  // levels too (a ratio of 1.5 or more on textured concrete); lit concrete
  // between two shadows is rougher than the shadowed (about the shadow's
  // light factor, 0.7 for a factor of 0.45). 0 turns the test off.
  double bar_min_roughness_ratio = 0.9;
  // A bright line's flanks (both sides of a ridge, the dark side of an edge)
  // fall within a cell or two: the steepest fall per cell over the whole fall
  // (internal::MeasureFlankSharpness, out to flank_max_cells) must be at
  // least this. Paint: 0.35-0.5 per cell (1 cm cells; motion blur across a
  // line lowers it); a glare band of sigma s cells: about 0.6 / s (3 cm:
  // 0.2). 0 turns the test off.
  double min_flank_sharpness = 0.25;
  int flank_max_cells = 15;
  // Bright side lobes of dark lines (see line_sides.h, DropSideLobes).
  double side_lobe_distance_cells = 8.0;
  double side_lobe_angle_deg = 3.0;
  // Lines of one polarity within this distance (of the shorter one's
  // endpoints from the longer one's line) and angle, overlapping over half of
  // the shorter, are one marking: duplicates from two Hough segments, or
  // the two bright ridges of a tape split by a joint running under it
  // (closer than the ridge filter resolves two markings: 2 sigma_cells).
  // They merge into their samples-weighted mean line (line_sides.h).
  double same_marking_distance_m = 0.06;
  double same_marking_angle_deg = 1.5;
  double orientation_tolerance_deg = 20.0;
  // Covariance (line_covariance.h, LineNoiseModel): the pixel noise of the
  // centres is measured on each line, at least min_sigma_px, from their
  // scatter with N / scatter_correlation_samples degrees of freedom (<= 0:
  // 4 sqrt(pi) sigma_cells, twice the ridge filter's own correlation
  // length: the BEV is smoothed before it); the covariance counts
  // correlation_samples centres per independent one (<= 0: 2.5
  // sigma_cells: the centres' errors are band-pass, positive to 9 cm and
  // negative from 10 to 35 cm (the floor's texture), so they average out
  // along a line faster than their scatter's correlation suggests;
  // single-edge points are independent); the floors hold errors constant
  // along a line that the scatter cannot show (a scuff or stain pulling a
  // stretch of it, the sub-cell phase of a line along the grid): an offset
  // of the line and a turn about its centroid (line_covariance.h).
  // Calibrated on the simulator datasets of seed 1 (with the vehicle's
  // path-following deviation), validated on seeds 2 and 3
  // (docs/perception.md, "Fourth round"). min_sigma_px: tapes the vehicle drives along
  // scatter by 0.1-0.3 px; a floor of 0.3 px put 10-16 % of the zone A tapes
  // below the NEES band.
  double min_sigma_px = 0.1;
  double correlation_samples = 0.0;
  double scatter_correlation_samples = 0.0;
  double rho_floor_m = 0.0004;
  double alpha_floor_rad = 0.00052;  // 0.03 deg
  bool floor_about_centroid = true;  // LineNoiseModel::floor_about_centroid
  // The calibration's floor uncertainty (calibration/bev_uncertainty.h,
  // written by `calibrate floor`); null: none. Each line's covariance is
  // raised to at least that of the line through its endpoints with the map's
  // covariances there (core::CovarianceAtLeast): a line is known no better
  // than the mount and intrinsics that put it on the floor. An endpoint in a
  // cell the map does not know is moved inward along the line (to 10 %, then
  // 25 % of its length); a line with no known pair keeps its covariance.
  std::shared_ptr<const calibration::BevUncertaintyMap> calibration_floor;

  core::Status Validate() const;
  // correlation_samples and scatter_correlation_samples with their defaults
  // (<= 0) resolved, each at least 1.
  double CorrelationSamples() const;
  double ScatterCorrelationSamples() const;

  // The preset for the localizer's smoother, which treats frames as
  // independent although a bias that a scuff, a stain or wear puts on a line
  // persists over every frame that sees it: one correlation length for the
  // scatter and the mean (ScatterCorrelationSamples), no rho floor, and a
  // 0.04 deg alpha floor about the foot of the origin. Tuned on the 1.2 km
  // loops of zones A-D (seed 11) for pose NEES (docs/perception.md,
  // "Covariance for the smoother").
  static LineExtractorOptions ForFusion();
};

struct ExtractedLine {
  HesseLine line;                                        // base_link
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  // (rho_m, alpha_rad)
  Eigen::Vector2d start_m = Eigen::Vector2d::Zero();     // endpoints on the line, base_link
  Eigen::Vector2d end_m = Eigen::Vector2d::Zero();
  LineKind kind;
  bool from_bar_edges = false;   // the centre line of two facing bar edges
  bool single_bar_edge = false;  // the step edge of a bar whose other edge is unseen
  double energy = 0.0;           // mean peak ridge energy
  double rms_residual_m = 0.0;   // of the centres about the fitted line
  int samples = 0;               // ridge centres fitted
  double noise_sigma_px = 0.0;   // the pixel noise of its centres (LineNoiseModel)

  double LengthM() const { return (end_m - start_m).norm(); }
};

struct LineExtraction {
  std::vector<ExtractedLine> lines;
  std::vector<Junction> junctions;  // indices into lines
  double bright_threshold = 0.0;    // energy thresholds used this frame
  double dark_threshold = 0.0;
};

// J_floor_pixel (d(x, y)/d(u, v), m/px) at every valid BEV cell centre,
// CV_64FC4 (row-major 2x2), zero where invalid: the analytic inverse of
// FloorProjection::PixelOfFloorPoint's Jacobian.
cv::Mat FloorFromPixelJacobians(const BevGrid& grid, const cv::Mat& valid_mask,
                                const calibration::FloorProjection& projection);

// The frame-sized images Extract works in: the BEV as float, the Hessian,
// the ridge images and the ridge centres. A caller that extracts frame after
// frame (the service's camera stage, the localizer) keeps one and passes it:
// the buffers are then allocated by the first frame and reused, instead of
// some 3 MB allocated and freed per frame, which fragments a long-running
// process's heap (docs/service.md, "Memory"). One per thread; its contents
// after a call are that call's intermediate images, not part of the result.
struct ExtractionScratch {
  cv::Mat bev_float;
  HessianImages hessian;
  RidgeImages ridges;
  RidgeScratch ridge;
  cv::Mat centres;
};

class LineExtractor {
 public:
  // For the BEV of `remap` (grid, valid cells, camera and mount). Options
  // must be valid (asserted).
  LineExtractor(const BevRemap& remap, const LineExtractorOptions& options);
  // General form: grid, valid mask (CV_8U), Jacobians as from
  // FloorFromPixelJacobians, and the camera's foot point (the floor point
  // below its centre, base_link) when known (the radial test needs it).
  LineExtractor(const BevGrid& grid, const cv::Mat& valid_mask, cv::Mat floor_from_pixel,
                const LineExtractorOptions& options,
                std::optional<Eigen::Vector2d> camera_foot_m = std::nullopt);

  // The lines of one BEV (CV_8UC1, grid-sized; asserted).
  LineExtraction Extract(const cv::Mat& bev) const;
  // The same, working in *scratch's buffers (not null). The result does not
  // depend on what *scratch held before.
  LineExtraction Extract(const cv::Mat& bev, ExtractionScratch* scratch) const;

  const BevGrid& grid() const { return grid_; }
  const LineExtractorOptions& options() const { return options_; }
  // The valid mask eroded by the border margin: where ridges count.
  const cv::Mat& search_mask() const { return search_mask_; }

 private:
  BevGrid grid_;
  LineExtractorOptions options_;
  SteerableRidgeFilter filter_;
  cv::Mat search_mask_;
  cv::Mat floor_from_pixel_;  // CV_64FC4
  std::optional<Eigen::Vector2d> camera_foot_m_;
  LineNoiseModel noise_;
};

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_LINE_EXTRACTOR_H_
