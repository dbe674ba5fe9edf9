// The per-frame line extraction pipeline (line_extractor.h).
#include "groundline/perception/line_extractor.h"

#include <Eigen/LU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>

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
  if (!(side_offset_cells > 0.0)) return bad("side_offset_cells", "a number > 0");
  if (!(bar_max_width_m > bar_min_width_m && bar_min_width_m >= 0.0)) {
    return bad("bar_min_width_m / bar_max_width_m", "0 <= min < max");
  }
  if (!(orientation_tolerance_deg > 0.0 && orientation_tolerance_deg < 45.0)) {
    return bad("orientation_tolerance_deg", "a number in (0, 45)");
  }
  if (!(sigma_px > 0.0) || !std::isfinite(sigma_px)) return bad("sigma_px", "a number > 0");
  if (!std::isfinite(correlation_samples)) return bad("correlation_samples", "a finite number");
  return core::Status::Ok();
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
          options) {}

LineExtractor::LineExtractor(const BevGrid& grid, const cv::Mat& valid_mask,
                             cv::Mat floor_from_pixel, const LineExtractorOptions& options)
    : grid_(grid),
      options_(options),
      filter_(options.ridge),
      floor_from_pixel_(std::move(floor_from_pixel)) {
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
  correlation_samples_ = options.correlation_samples > 0.0
                             ? options.correlation_samples
                             : 2.0 * std::sqrt(std::numbers::pi) * options.ridge.sigma_cells;
  correlation_samples_ = std::max(1.0, correlation_samples_);
}

namespace {

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

// One merged segment -> a fitted line, or nothing when it fails a test.
std::optional<internal::CandidateLine> FitSegment(
    const RidgeImagesView& view, const RidgeSegment& segment, double threshold,
    const cv::Mat& search_mask, const cv::Mat& floor_from_pixel, const BevGrid& grid,
    const LineExtractorOptions& options, double correlation_samples) {
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
  if (samples.size() < 3) return std::nullopt;
  const double span_cells = samples.back().along_cell - samples.front().along_cell;
  if (span_cells * grid.cell_m() < options.min_line_length_m) return std::nullopt;
  if (static_cast<double>(samples.size()) < options.min_support * (span_cells + 1.0)) {
    return std::nullopt;
  }
  std::vector<double> widths, energies;
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
  std::vector<Eigen::Matrix2d> jacobians;
  for (const RidgeSample& s : samples) {
    candidate.centres_m.push_back(grid.FloorPointOfCell(s.centre_cell));
    const cv::Vec4d& j =
        floor_from_pixel.at<cv::Vec4d>(static_cast<int>(std::lround(s.centre_cell.y())),
                                       static_cast<int>(std::lround(s.centre_cell.x())));
    Eigen::Matrix2d J;
    J << j[0], j[1], j[2], j[3];
    jacobians.push_back(J);
  }
  core::Result<LineFit> fit =
      FitLineWithPixelNoise(candidate.centres_m, jacobians, options.sigma_px, correlation_samples);
  if (!fit.ok()) return std::nullopt;
  ExtractedLine& line = candidate.line;
  line.line = fit->line;
  line.covariance = fit->covariance;
  line.rms_residual_m = fit->rms_residual_m;
  line.samples = static_cast<int>(samples.size());
  line.energy = Mean(energies);
  const Eigen::Vector2d foot = line.line.rho_m * line.line.Normal();
  const Eigen::Vector2d d = line.line.Direction();
  line.start_m = foot + d.dot(candidate.centres_m.front()) * d;
  line.end_m = foot + d.dot(candidate.centres_m.back()) * d;
  return candidate;
}

}  // namespace

LineExtraction LineExtractor::Extract(const cv::Mat& bev) const {
  assert(bev.type() == CV_8UC1 && bev.rows == grid_.rows() && bev.cols == grid_.cols());
  HessianImages hessian;
  filter_.Compute(bev, &hessian);
  RidgeImages ridges;
  AnalyzeRidges(hessian, &ridges);
  cv::Mat bev_float;
  bev.convertTo(bev_float, CV_32F);

  LineExtraction result;
  const double side_offset_m = options_.side_offset_cells * grid_.cell_m();
  const double floor_median_grey = internal::MedianGrey(bev, search_mask_);
  for (const LinePolarity polarity : {LinePolarity::kBright, LinePolarity::kDark}) {
    const bool bright = polarity == LinePolarity::kBright;
    if (bright ? !options_.bright : !options_.dark) continue;
    const cv::Mat& energy = bright ? ridges.bright : ridges.dark;
    const double threshold = RidgeEnergyThreshold(energy, search_mask_, options_.segments);
    (bright ? result.bright_threshold : result.dark_threshold) = threshold;
    cv::Mat centres;
    RidgeCentreMask(energy, ridges.eigen_ratio, ridges.normal_rad, search_mask_, threshold,
                    options_.segments, &centres);
    const std::vector<RidgeSegment> segments =
        MergeCollinearSegments(HoughSegments(centres, options_.segments), options_.segments);
    const RidgeImagesView view{&energy, &ridges.eigen_ratio, &ridges.normal_rad};
    std::vector<internal::CandidateLine> candidates;
    for (const RidgeSegment& segment : segments) {
      std::optional<internal::CandidateLine> candidate =
          FitSegment(view, segment, threshold, search_mask_, floor_from_pixel_, grid_, options_,
                     correlation_samples_);
      if (!candidate) continue;
      candidate->line.kind.polarity = polarity;
      internal::MeasureSideContrast(bev_float, grid_, side_offset_m, &*candidate);
      candidates.push_back(std::move(*candidate));
    }
    internal::SelectLines(std::move(candidates), polarity, floor_median_grey, options_,
                          &result.lines);
  }
  internal::MergeDuplicateLines(&result.lines);
  const double tolerance_rad = options_.orientation_tolerance_deg * std::numbers::pi / 180.0;
  std::vector<LineSegmentEstimate> estimates;
  for (ExtractedLine& line : result.lines) {
    line.kind.orientation = ClassifyOrientation(line.line, tolerance_rad);
    estimates.push_back({line.line, line.covariance, line.start_m, line.end_m});
  }
  result.junctions = FindJunctions(estimates, options_.junctions);
  return result;
}

}  // namespace groundline::perception
