// The per-frame line extraction pipeline (line_extractor.h).
#include "groundline/perception/line_extractor.h"

#include <Eigen/LU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/core/covariance.h"
#include "groundline/perception/line_covariance.h"
#include "line_sides.h"

namespace groundline::perception {

core::Status LineExtractorOptions::Validate() const {
  if (core::Status s = ridge.Validate(); !s.ok()) return s;
  if (core::Status s = segments.Validate(); !s.ok()) return s;
  if (core::Status s = junctions.Validate(); !s.ok()) return s;
  auto bad = [](const std::string& field, const std::string& expected) {
    return core::Status::Error("LineExtractorOptions." + field + ": expected " + expected);
  };
  if (refinement.search_half_width_cells < 2) {
    return bad("refinement.search_half_width_cells", "an integer >= 2");
  }
  if (!(border_erosion_sigmas >= 0.0)) return bad("border_erosion_sigmas", "a number >= 0");
  if (!(sample_energy_fraction > 0.0 && sample_energy_fraction <= 1.0)) {
    return bad("sample_energy_fraction", "a number in (0, 1]");
  }
  if (!(outlier_cells > 0.0)) return bad("outlier_cells", "a number > 0");
  if (!(min_line_length_m > 0.0)) return bad("min_line_length_m", "a number > 0");
  if (!(min_support >= 0.0 && min_support <= 1.0)) return bad("min_support", "a number in [0, 1]");
  if (!(max_width_variation > 0.0)) return bad("max_width_variation", "a number > 0");
  if (!(width_outlier_fraction > 0.0)) return bad("width_outlier_fraction", "a number > 0");
  if (!(dark_narrow_offset_cells > 0.0 && dark_narrow_offset_cells < side_offset_cells)) {
    return bad("dark_narrow_offset_cells", "a number in (0, side_offset_cells)");
  }
  if (!(min_dark_narrow_share >= 0.0 && min_dark_narrow_share <= 1.0)) {
    return bad("min_dark_narrow_share", "a number in [0, 1]");
  }
  if (!(max_dark_sagitta_m > 0.0)) return bad("max_dark_sagitta_m", "a number > 0");
  if (!(dark_sagitta_significance >= 0.0)) {
    return bad("dark_sagitta_significance", "a number >= 0");
  }
  if (!(dark_min_significant_sagitta_m >= 0.0)) {
    return bad("dark_min_significant_sagitta_m", "a number >= 0");
  }
  if (!(dark_arc_max_radius_m >= 0.0)) return bad("dark_arc_max_radius_m", "a number >= 0");
  if (!(dark_short_length_m >= 0.0)) return bad("dark_short_length_m", "a number >= 0");
  if (!(dark_short_max_rms_m > 0.0)) return bad("dark_short_max_rms_m", "a number > 0");
  if (!(min_bright_side_ratio >= 0.0 && min_bright_side_ratio <= 1.0)) {
    return bad("min_bright_side_ratio", "a number in [0, 1]");
  }
  if (!(bright_side_min_grey_share >= 0.0)) {
    return bad("bright_side_min_grey_share", "a number >= 0");
  }
  if (!(reference_floor_grey >= 0.0 && reference_floor_grey <= 255.0)) {
    return bad("reference_floor_grey", "a grey level in [0, 255] (0: off)");
  }
  if (!(same_marking_distance_m >= 0.0)) return bad("same_marking_distance_m", "a number >= 0");
  if (!(same_marking_angle_deg >= 0.0)) return bad("same_marking_angle_deg", "a number >= 0");
  if (!(side_offset_cells > 0.0)) return bad("side_offset_cells", "a number > 0");
  if (!(bar_max_width_m > bar_min_width_m && bar_min_width_m >= 0.0)) {
    return bad("bar_min_width_m / bar_max_width_m", "0 <= min < max");
  }
  if (!(min_bright_excess >= 0.0)) return bad("min_bright_excess", "a number >= 0");
  if (!(side_lobe_distance_cells >= 0.0)) return bad("side_lobe_distance_cells", "a number >= 0");
  if (!(side_lobe_angle_deg >= 0.0)) return bad("side_lobe_angle_deg", "a number >= 0");
  if (!(single_edge_min_contrast > 0.0)) return bad("single_edge_min_contrast", "a number > 0");
  if (!(single_edge_max_gap_m > 0.0)) return bad("single_edge_max_gap_m", "a number > 0");
  if (!(single_edge_min_length_m > 0.0)) return bad("single_edge_min_length_m", "a number > 0");
  if (!(single_edge_extension_m >= 0.0)) return bad("single_edge_extension_m", "a number >= 0");
  if (!(single_edge_max_radial_deg >= 0.0 && single_edge_max_radial_deg <= 45.0)) {
    return bad("single_edge_max_radial_deg", "a number in [0, 45]");
  }
  if (!(ray_line_max_angle_deg >= 0.0 && ray_line_max_angle_deg <= 45.0)) {
    return bad("ray_line_max_angle_deg", "a number in [0, 45]");
  }
  if (!(ray_line_max_width_growth >= 0.0)) return bad("ray_line_max_width_growth", "a number >= 0");
  if (!(ray_line_half_width_m > 0.0)) return bad("ray_line_half_width_m", "a number > 0");
  if (!(ray_line_min_width_increase_m >= 0.0)) {
    return bad("ray_line_min_width_increase_m", "a number >= 0");
  }
  if (!(single_edge_min_relative_contrast > 0.0 && single_edge_min_relative_contrast <= 1.0)) {
    return bad("single_edge_min_relative_contrast", "a number in (0, 1]");
  }
  if (!(orientation_tolerance_deg > 0.0 && orientation_tolerance_deg < 45.0)) {
    return bad("orientation_tolerance_deg", "a number in (0, 45)");
  }
  if (!std::isfinite(correlation_samples)) return bad("correlation_samples", "a finite number");
  if (!std::isfinite(scatter_correlation_samples)) {
    return bad("scatter_correlation_samples", "a finite number");
  }
  LineNoiseModel noise;
  noise.min_sigma_px = min_sigma_px;
  noise.rho_floor_m = rho_floor_m;
  noise.alpha_floor_rad = alpha_floor_rad;
  if (core::Status s = noise.Validate(); !s.ok()) return s;
  return core::Status::Ok();
}

double LineExtractorOptions::CorrelationSamples() const {
  return std::max(1.0, correlation_samples > 0.0 ? correlation_samples : 2.5 * ridge.sigma_cells);
}

LineExtractorOptions LineExtractorOptions::ForFusion() {
  LineExtractorOptions options;
  options.correlation_samples = options.ScatterCorrelationSamples();
  options.rho_floor_m = 0.0;
  options.alpha_floor_rad = 0.0007;  // 0.04 deg
  options.floor_about_centroid = false;
  return options;
}

double LineExtractorOptions::ScatterCorrelationSamples() const {
  return std::max(1.0, scatter_correlation_samples > 0.0
                           ? scatter_correlation_samples
                           : 4.0 * std::sqrt(std::numbers::pi) * ridge.sigma_cells);
}

cv::Mat FloorFromPixelJacobians(const BevGrid& grid, const cv::Mat& valid_mask,
                                const calibration::FloorProjection& projection) {
  cv::Mat table(grid.rows(), grid.cols(), CV_64FC4, cv::Scalar::all(0));
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      if (valid_mask.at<std::uint8_t>(r, c) == 0) continue;
      Eigen::Matrix2d J_pixel_floor;
      const Eigen::Vector2d floor = grid.FloorPointOfCell(Eigen::Vector2d(c, r));
      if (!projection.PixelOfFloorPoint(floor, &J_pixel_floor).ok()) continue;
      if (std::abs(J_pixel_floor.determinant()) < 1e-12) continue;
      const Eigen::Matrix2d J = J_pixel_floor.inverse();
      table.at<cv::Vec4d>(r, c) = cv::Vec4d(J(0, 0), J(0, 1), J(1, 0), J(1, 1));
    }
  }
  return table;
}

LineExtractor::LineExtractor(const BevRemap& remap, const LineExtractorOptions& options)
    : LineExtractor(
          remap.grid(), remap.valid_mask(),
          FloorFromPixelJacobians(remap.grid(), remap.valid_mask(),
                                  calibration::FloorProjection(remap.camera(), remap.mount())),
          options, calibration::BaseFromCamera(remap.mount()).translation().head<2>()) {}

LineExtractor::LineExtractor(const BevGrid& grid, const cv::Mat& valid_mask,
                             cv::Mat floor_from_pixel, const LineExtractorOptions& options,
                             std::optional<Eigen::Vector2d> camera_foot_m)
    : grid_(grid),
      options_(options),
      filter_(options.ridge),
      floor_from_pixel_(std::move(floor_from_pixel)),
      camera_foot_m_(std::move(camera_foot_m)) {
  assert(options.Validate().ok());
  assert(valid_mask.rows == grid.rows() && valid_mask.cols == grid.cols());
  assert(floor_from_pixel_.type() == CV_64FC4 && floor_from_pixel_.size() == valid_mask.size());
  const int radius =
      static_cast<int>(std::ceil(options.border_erosion_sigmas * options.ridge.sigma_cells));
  cv::Mat valid = valid_mask.clone();
  // The grid's own border is unseen too.
  cv::rectangle(valid, cv::Rect(0, 0, valid.cols, valid.rows), cv::Scalar(0), 1);
  cv::erode(valid, search_mask_,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1)));
  noise_.correlation_samples = options.CorrelationSamples();
  noise_.scatter_correlation_samples = options.ScatterCorrelationSamples();
  noise_.min_sigma_px = options.min_sigma_px;
  noise_.rho_floor_m = options.rho_floor_m;
  noise_.alpha_floor_rad = options.alpha_floor_rad;
  noise_.floor_about_centroid = options.floor_about_centroid;
}

namespace {

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

// The weighted TLS line through floor points (base_link) with the covariance
// of line_covariance.h from the back-projection Jacobian of each point's BEV
// cell; fills line, covariance, rms_residual_m, samples and the endpoints
// (the first and last point projected onto the line). False when a point is
// off the grid or the fit fails.
bool FitFloorPoints(const std::vector<Eigen::Vector2d>& points_m, const BevGrid& grid,
                    const cv::Mat& floor_from_pixel, const LineNoiseModel& noise,
                    ExtractedLine* line) {
  std::vector<Eigen::Matrix2d> jacobians;
  jacobians.reserve(points_m.size());
  for (const Eigen::Vector2d& p : points_m) {
    const Eigen::Vector2d cell = grid.CellOfFloorPoint(p);
    const int c = static_cast<int>(std::lround(cell.x()));
    const int r = static_cast<int>(std::lround(cell.y()));
    if (c < 0 || r < 0 || c >= floor_from_pixel.cols || r >= floor_from_pixel.rows) return false;
    const cv::Vec4d& j = floor_from_pixel.at<cv::Vec4d>(r, c);
    Eigen::Matrix2d J;
    J << j[0], j[1], j[2], j[3];
    jacobians.push_back(J);
  }
  core::Result<LineFit> fit =
      FitLineWithMeasuredNoise(points_m, jacobians, noise, &line->noise_sigma_px);
  if (!fit.ok()) return false;
  line->line = fit->line;
  line->covariance = fit->covariance;
  line->rms_residual_m = fit->rms_residual_m;
  line->samples = static_cast<int>(points_m.size());
  const Eigen::Vector2d foot = line->line.rho_m * line->line.Normal();
  const Eigen::Vector2d d = line->line.Direction();
  line->start_m = foot + d.dot(points_m.front()) * d;
  line->end_m = foot + d.dot(points_m.back()) * d;
  return true;
}

// LineExtractorOptions::calibration_floor on one line.
void ApplyCalibrationFloor(const calibration::BevUncertaintyMap& map, ExtractedLine* line) {
  for (const double t : {0.0, 0.1, 0.25}) {
    const Eigen::Vector2d p1 = line->start_m + t * (line->end_m - line->start_m);
    const Eigen::Vector2d p2 = line->end_m + t * (line->start_m - line->end_m);
    const std::optional<Eigen::Matrix2d> s1 = map.CovarianceAt(p1);
    const std::optional<Eigen::Matrix2d> s2 = map.CovarianceAt(p2);
    if (!s1 || !s2) continue;
    const core::Result<LineEstimate> floor = LineFromEndpoints(p1, *s1, p2, *s2);
    if (!floor.ok()) return;
    line->covariance = core::CovarianceAtLeast<2>(
        line->covariance, CovarianceInDescriptionOf(floor->line, line->line, floor->covariance));
    return;
  }
}

// One merged segment -> a fitted line, or nothing when it fails a test.
std::optional<internal::CandidateLine> FitSegment(
    const RidgeImagesView& view, const cv::Mat& bev_float, LinePolarity polarity,
    const RidgeSegment& segment, double threshold, const cv::Mat& search_mask,
    const cv::Mat& floor_from_pixel, const BevGrid& grid, const LineExtractorOptions& options,
    const LineNoiseModel& noise) {
  int positions = 0;
  std::vector<RidgeSample> samples = RefineRidgeCentres(
      view, segment, options.sample_energy_fraction * threshold, options.refinement, &positions);
  std::erase_if(samples, [&](const RidgeSample& s) {
    const int c = static_cast<int>(std::lround(s.centre_cell.x()));
    const int r = static_cast<int>(std::lround(s.centre_cell.y()));
    return search_mask.at<std::uint8_t>(r, c) == 0;
  });
  if (samples.size() < 3) return std::nullopt;
  std::vector<Eigen::Vector2d> cells;
  cells.reserve(samples.size());
  for (const RidgeSample& s : samples) cells.push_back(s.centre_cell);
  core::Result<LineFit> first = FitLineTls(cells, {}, 1.0);
  if (!first.ok()) return std::nullopt;
  std::erase_if(samples, [&](const RidgeSample& s) {
    return std::abs(SignedDistance(first->line, s.centre_cell)) > options.outlier_cells;
  });
  // Width outliers: where something crosses or overlaps the line.
  std::vector<double> widths;
  for (const RidgeSample& s : samples) widths.push_back(s.width_cells);
  std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
  const double median_width = widths[widths.size() / 2];
  std::erase_if(samples, [&](const RidgeSample& s) {
    return std::abs(s.width_cells - median_width) > options.width_outlier_fraction * median_width;
  });
  if (samples.size() < 3) return std::nullopt;
  // Lopsided floor beside a joint (LineExtractorOptions::max_side_asymmetry).
  if (polarity == LinePolarity::kDark && options.max_side_asymmetry > 0.0) {
    const Eigen::Vector2d n = first->line.Normal();  // cells
    std::erase_if(samples, [&](const RidgeSample& s) {
      const Eigen::Vector2d& c = s.centre_cell;
      const Eigen::Vector2d a = c + options.side_offset_cells * n;
      const Eigen::Vector2d b = c - options.side_offset_cells * n;
      const double centre = SampleBilinear(bev_float, c.x(), c.y());
      const double side_a = SampleBilinear(bev_float, a.x(), a.y());
      const double side_b = SampleBilinear(bev_float, b.x(), b.y());
      const double depth = 0.5 * (side_a + side_b) - centre;  // dark: the sides are brighter
      return depth > 0.0 && std::abs(side_a - side_b) > options.max_side_asymmetry * depth;
    });
    if (samples.size() < 3) return std::nullopt;
  }
  const double span_cells = samples.back().along_cell - samples.front().along_cell;
  if (span_cells * grid.cell_m() < options.min_line_length_m) return std::nullopt;
  if (static_cast<double>(samples.size()) < options.min_support * (span_cells + 1.0)) {
    return std::nullopt;
  }
  std::vector<double> energies;
  widths.clear();
  for (const RidgeSample& s : samples) {
    widths.push_back(s.width_cells);
    energies.push_back(s.energy);
  }
  const double mean_width = Mean(widths);
  double width_var = 0.0;
  for (double w : widths) width_var += (w - mean_width) * (w - mean_width);
  width_var /= static_cast<double>(widths.size());
  if (std::sqrt(width_var) > options.max_width_variation * mean_width) return std::nullopt;

  internal::CandidateLine candidate;
  for (const RidgeSample& s : samples) {
    candidate.centres_m.push_back(grid.FloorPointOfCell(s.centre_cell));
  }
  if (!FitFloorPoints(candidate.centres_m, grid, floor_from_pixel, noise, &candidate.line)) {
    return std::nullopt;
  }
  candidate.line.energy = Mean(energies);
  candidate.sagitta = internal::MeasureSagitta(candidate.line.line, candidate.centres_m,
                                               options.CorrelationSamples());
  return candidate;
}

// The edge line of a bar whose other edge is unseen (internal::LocateBarEdge),
// or nothing when too few edge points line up.
std::optional<ExtractedLine> FitSingleBarEdge(const cv::Mat& bev_float, const cv::Mat& search_mask,
                                              const internal::CandidateLine& candidate,
                                              const cv::Mat& floor_from_pixel, const BevGrid& grid,
                                              const LineExtractorOptions& options,
                                              const LineNoiseModel& noise) {
  // The ridge of a bar's inner flank fades near the bar's corners and the
  // footprint's border before the edge ends: the edge is also looked for
  // beyond the ridge's ends, along its line (where there is no step, the bar
  // has ended and LocateBarEdge finds nothing).
  internal::CandidateLine extended = candidate;
  const Eigen::Vector2d ridge_d = candidate.line.line.Direction();
  const Eigen::Vector2d foot = candidate.line.line.rho_m * candidate.line.line.Normal();
  double lo = ridge_d.dot(candidate.centres_m.front()), hi = lo;
  for (const Eigen::Vector2d& p : candidate.centres_m) {
    lo = std::min(lo, ridge_d.dot(p));
    hi = std::max(hi, ridge_d.dot(p));
  }
  const int steps = static_cast<int>(std::floor(options.single_edge_extension_m / grid.cell_m()));
  for (int k = 1; k <= steps; ++k) {
    for (const double along : {lo - k * grid.cell_m(), hi + k * grid.cell_m()}) {
      const Eigen::Vector2d p = foot + along * ridge_d;
      const Eigen::Vector2d cell = grid.CellOfFloorPoint(p);
      const int c = static_cast<int>(std::lround(cell.x()));
      const int r = static_cast<int>(std::lround(cell.y()));
      if (c < 0 || r < 0 || c >= search_mask.cols || r >= search_mask.rows ||
          search_mask.at<std::uint8_t>(r, c) == 0) {
        continue;
      }
      extended.centres_m.push_back(p);
    }
  }
  std::vector<Eigen::Vector2d> points =
      internal::LocateBarEdge(bev_float, grid, extended, options.single_edge_min_contrast);
  if (points.size() < 3 || points.size() < options.min_support * candidate.centres_m.size()) {
    return std::nullopt;
  }
  core::Result<LineFit> first = FitLineTls(points, {}, 1.0);
  if (!first.ok()) return std::nullopt;
  const double outlier_m = options.outlier_cells * grid.cell_m();
  std::erase_if(points, [&](const Eigen::Vector2d& p) {
    return std::abs(SignedDistance(first->line, p)) > outlier_m;
  });
  if (points.size() < 3) return std::nullopt;
  // The longest run of points without a gap: the ends of bars (no longer than
  // a bar is wide) and rows of them (a crosswalk's stripe ends) are no edge
  // line.
  const Eigen::Vector2d d = first->line.Direction();
  std::sort(points.begin(), points.end(), [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return d.dot(a) < d.dot(b);
  });
  size_t run_begin = 0, best_begin = 0, best_end = 1;
  for (size_t i = 1; i <= points.size(); ++i) {
    if (i == points.size() || d.dot(points[i] - points[i - 1]) > options.single_edge_max_gap_m) {
      if (d.dot(points[i - 1] - points[run_begin]) >
          d.dot(points[best_end - 1] - points[best_begin])) {
        best_begin = run_begin;
        best_end = i;
      }
      run_begin = i;
    }
  }
  points = std::vector<Eigen::Vector2d>(points.begin() + best_begin, points.begin() + best_end);
  if (points.size() < 3 ||
      d.dot(points.back() - points.front()) < options.single_edge_min_length_m) {
    return std::nullopt;
  }
  if (internal::OpenBrightSideShare(bev_float, search_mask, grid, candidate, points,
                                    options.bar_max_width_m) < 0.5) {
    return std::nullopt;
  }
  if (options.single_edge_min_roughness_ratio > 0.0) {
    const internal::SideRoughness rough = internal::MeasureSideRoughness(
        bev_float, grid, candidate, points, options.single_edge_roughness_near_m,
        options.single_edge_roughness_far_m);
    if (!(rough.dark >= options.single_edge_min_roughness_ratio * rough.bright)) {
      return std::nullopt;
    }
  }
  // Each edge point comes from its own profile, unsmoothed along the line:
  // the points are independent. The rho floor stays: the steepest step sits
  // at a sub-cell phase that is the same all along a line running along the
  // grid (zone A stripe edges: errors of 0.2-1.4 mm at 0.1 mm scatter once
  // the simulated vehicle no longer drove exactly on the lane centre).
  LineNoiseModel independent = noise;
  independent.correlation_samples = 1.0;
  independent.scatter_correlation_samples = 1.0;
  ExtractedLine line = candidate.line;
  if (!FitFloorPoints(points, grid, floor_from_pixel, independent, &line)) {
    return std::nullopt;
  }
  line.single_bar_edge = true;
  return line;
}

// The angle between the line and the ray from `foot_m` to its midpoint, in
// [0, pi/2]; pi/2 when the midpoint is at the foot point.
double RayAngleRad(const ExtractedLine& line, const Eigen::Vector2d& foot_m) {
  const Eigen::Vector2d ray = 0.5 * (line.start_m + line.end_m) - foot_m;
  const Eigen::Vector2d along = line.end_m - line.start_m;
  if (ray.norm() < 1e-9 || along.norm() < 1e-9) return std::numbers::pi / 2.0;
  const double cross = std::abs(ray.x() * along.y() - ray.y() * along.x());
  return std::atan2(cross, std::abs(ray.dot(along)));
}

}  // namespace

LineExtraction LineExtractor::Extract(const cv::Mat& bev) const {
  ExtractionScratch scratch;
  return Extract(bev, &scratch);
}

LineExtraction LineExtractor::Extract(const cv::Mat& bev, ExtractionScratch* scratch) const {
  assert(bev.type() == CV_8UC1 && bev.rows == grid_.rows() && bev.cols == grid_.cols());
  assert(scratch != nullptr);
  // Exposure: the grey-level thresholds are for a floor of the reference
  // grey; a darker frame is scaled up to it (LineExtractorOptions::reference_floor_grey).
  double floor_median_grey = internal::MedianGrey(bev, search_mask_);
  double gain = 1.0;
  if (options_.reference_floor_grey > 0.0 && floor_median_grey > 0.0) {
    gain = std::max(1.0, options_.reference_floor_grey / floor_median_grey);
    floor_median_grey *= gain;
  }
  bev.convertTo(scratch->bev_float, CV_32F, gain);
  const cv::Mat& bev_float = scratch->bev_float;
  filter_.Compute(bev_float, &scratch->hessian);
  AnalyzeRidges(scratch->hessian, &scratch->ridges, &scratch->ridge);
  const RidgeImages& ridges = scratch->ridges;

  LineExtraction result;
  const double side_offset_m = options_.side_offset_cells * grid_.cell_m();
  for (const LinePolarity polarity : {LinePolarity::kBright, LinePolarity::kDark}) {
    const bool bright = polarity == LinePolarity::kBright;
    if (bright ? !options_.bright : !options_.dark) continue;
    const cv::Mat& energy = bright ? ridges.bright : ridges.dark;
    RidgeSegmentOptions segment_options = options_.segments;
    if (!bright && options_.dark_max_energy > 0.0) {
      segment_options.max_energy = std::max(segment_options.min_energy, options_.dark_max_energy);
    }
    const double threshold = RidgeEnergyThreshold(energy, search_mask_, segment_options);
    (bright ? result.bright_threshold : result.dark_threshold) = threshold;
    RidgeCentreMask(energy, ridges.eigen_ratio, ridges.normal_rad, search_mask_, threshold,
                    options_.segments, &scratch->centres);
    const std::vector<RidgeSegment> segments = MergeCollinearSegments(
        HoughSegments(scratch->centres, options_.segments), options_.segments);
    const RidgeImagesView view{&energy, &ridges.eigen_ratio, &ridges.normal_rad};
    std::vector<internal::CandidateLine> candidates;
    for (const RidgeSegment& segment : segments) {
      std::optional<internal::CandidateLine> candidate =
          FitSegment(view, bev_float, polarity, segment, threshold, search_mask_, floor_from_pixel_,
                     grid_, options_, noise_);
      if (!candidate) continue;
      candidate->line.kind.polarity = polarity;
      internal::MeasureSideContrast(bev_float, grid_, side_offset_m,
                                    options_.dark_narrow_offset_cells * grid_.cell_m(),
                                    0.5 * options_.min_dark_side_contrast, &*candidate);
      candidates.push_back(std::move(*candidate));
    }
    std::vector<internal::CandidateLine> unpaired_edges;
    internal::SelectLines(std::move(candidates), polarity, floor_median_grey, bev_float, grid_,
                          options_, &result.lines,
                          options_.single_bar_edges ? &unpaired_edges : nullptr);
    for (const internal::CandidateLine& edge : unpaired_edges) {
      if (std::max(edge.contrast_plus, edge.contrast_minus) < options_.single_edge_min_contrast) {
        continue;
      }
      std::optional<ExtractedLine> line = FitSingleBarEdge(
          bev_float, search_mask_, edge, floor_from_pixel_, grid_, options_, noise_);
      if (!line) continue;
      if (camera_foot_m_ && options_.single_edge_max_radial_deg > 0.0 &&
          RayAngleRad(*line, *camera_foot_m_) <=
              options_.single_edge_max_radial_deg * std::numbers::pi / 180.0) {
        continue;  // the vertical edge of a thing standing on the floor
      }
      result.lines.push_back(*line);
    }
  }
  if (camera_foot_m_ && options_.ray_line_max_width_growth > 0.0) {
    const double max_angle = options_.ray_line_max_angle_deg * std::numbers::pi / 180.0;
    std::erase_if(result.lines, [&](const ExtractedLine& line) {
      // Bright only: a dark post wider than a joint already fails the dark
      // lines' narrowness test, and joints along a ray must not be risked.
      if (line.kind.polarity != LinePolarity::kBright || line.single_bar_edge ||
          RayAngleRad(line, *camera_foot_m_) > max_angle) {
        return false;
      }
      // NaN (not measured) keeps the line.
      const internal::WidthGrowth growth = internal::WidthGrowthWithRange(
          bev_float, grid_, line, *camera_foot_m_, options_.ray_line_half_width_m);
      return growth.relative > options_.ray_line_max_width_growth &&
             growth.increase_m >= options_.ray_line_min_width_increase_m;
    });
  }
  internal::DropSideLobes(options_.side_lobe_distance_cells * grid_.cell_m(),
                          options_.side_lobe_angle_deg * std::numbers::pi / 180.0, &result.lines);
  internal::MergeSameMarkingLines(options_.same_marking_distance_m,
                                  options_.same_marking_angle_deg * std::numbers::pi / 180.0,
                                  &result.lines);
  const double tolerance_rad = options_.orientation_tolerance_deg * std::numbers::pi / 180.0;
  std::vector<LineSegmentEstimate> estimates;
  for (ExtractedLine& line : result.lines) {
    if (options_.calibration_floor) ApplyCalibrationFloor(*options_.calibration_floor, &line);
    line.kind.orientation = ClassifyOrientation(line.line, tolerance_rad);
    estimates.push_back({line.line, line.covariance, line.start_m, line.end_m});
  }
  result.junctions = FindJunctions(estimates, options_.junctions);
  return result;
}

}  // namespace groundline::perception
