// Otsu, non-maximum suppression, Hough and collinear merging (ridge_segments.h).
#include "groundline/perception/ridge_segments.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <string>

namespace groundline::perception {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

}  // namespace

core::Status RidgeSegmentOptions::Validate() const {
  auto bad = [](const std::string& field, const std::string& expected) {
    return core::Status::Error("RidgeSegmentOptions." + field + ": expected " + expected);
  };
  if (!(otsu_energy_range > 0.0) || !std::isfinite(otsu_energy_range))
    return bad("otsu_energy_range", "a finite number > 0");
  if (!(min_energy >= 0.0) || !std::isfinite(min_energy)) return bad("min_energy", "a number >= 0");
  if (!(max_energy >= min_energy) || !std::isfinite(max_energy)) {
    return bad("max_energy", "a finite number >= min_energy");
  }
  if (!(max_eigen_ratio > 0.0 && max_eigen_ratio <= 1.0))
    return bad("max_eigen_ratio", "a number in (0, 1]");
  if (hough_votes < 1) return bad("hough_votes", "an integer >= 1");
  if (!(hough_min_length_cells >= 2.0)) return bad("hough_min_length_cells", "a number >= 2");
  if (!(hough_max_gap_cells >= 0.0)) return bad("hough_max_gap_cells", "a number >= 0");
  if (!(merge_angle_deg >= 0.0 && merge_angle_deg < 45.0))
    return bad("merge_angle_deg", "a number in [0, 45)");
  if (!(merge_offset_cells >= 0.0)) return bad("merge_offset_cells", "a number >= 0");
  if (!(merge_gap_cells >= 0.0)) return bad("merge_gap_cells", "a number >= 0");
  return core::Status::Ok();
}

int OtsuThreshold(std::span<const double> histogram) {
  double total = 0.0, moment = 0.0;
  for (size_t i = 0; i < histogram.size(); ++i) {
    total += histogram[i];
    moment += static_cast<double>(i) * histogram[i];
  }
  if (total <= 0.0) return 0;
  double below = 0.0, below_moment = 0.0, best = -1.0;
  int best_t = 0;
  for (size_t t = 0; t + 1 < histogram.size(); ++t) {
    below += histogram[t];
    below_moment += static_cast<double>(t) * histogram[t];
    const double above = total - below;
    if (below <= 0.0 || above <= 0.0) continue;
    const double mean_below = below_moment / below;
    const double mean_above = (moment - below_moment) / above;
    const double between = below * above * (mean_below - mean_above) * (mean_below - mean_above);
    if (between > best) {
      best = between;
      best_t = static_cast<int>(t);
    }
  }
  return best_t;
}

double RidgeEnergyThreshold(const cv::Mat& energy, const cv::Mat& mask,
                            const RidgeSegmentOptions& options) {
  const double scale = 255.0 / options.otsu_energy_range;
  double histogram[256] = {};
  for (int r = 0; r < energy.rows; ++r) {
    const float* e = energy.ptr<float>(r);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < energy.cols; ++c) {
      if (m[c] == 0) continue;
      const int bin = std::clamp(static_cast<int>(e[c] * scale), 0, 255);
      histogram[bin] += 1.0;
    }
  }
  const double otsu = (OtsuThreshold(histogram) + 1) / scale;
  return std::clamp(otsu, options.min_energy, std::max(options.min_energy, options.max_energy));
}

void RidgeCentreMask(const cv::Mat& energy, const cv::Mat& eigen_ratio, const cv::Mat& normal_rad,
                     const cv::Mat& mask, double threshold, const RidgeSegmentOptions& options,
                     cv::Mat* centres) {
  centres->create(energy.size(), CV_8U);
  centres->setTo(0);
  const auto max_ratio = static_cast<float>(options.max_eigen_ratio);
  const auto t = static_cast<float>(threshold);
  const float kPi8 = static_cast<float>(std::numbers::pi / 8.0);
  for (int r = 1; r + 1 < energy.rows; ++r) {
    const float* e = energy.ptr<float>(r);
    const float* ratio = eigen_ratio.ptr<float>(r);
    const float* angle = normal_rad.ptr<float>(r);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    std::uint8_t* out = centres->ptr<std::uint8_t>(r);
    for (int c = 1; c + 1 < energy.cols; ++c) {
      if (e[c] <= t || m[c] == 0 || ratio[c] > max_ratio) continue;
      // The normal (cos a, sin a), a in (-pi/2, pi/2], to the nearest of 4 directions.
      const float a = angle[c];
      int dc = 1, dr = 0;
      if (a > 3 * kPi8 || a <= -3 * kPi8) {
        dc = 0;
        dr = 1;
      } else if (a > kPi8) {
        dr = 1;
      } else if (a <= -kPi8) {
        dr = -1;
      }
      const float before = energy.ptr<float>(r - dr)[c - dc];
      const float after = energy.ptr<float>(r + dr)[c + dc];
      if (e[c] >= before && e[c] >= after) out[c] = 255;
    }
  }
}

std::vector<RidgeSegment> HoughSegments(const cv::Mat& centres,
                                        const RidgeSegmentOptions& options) {
  std::vector<cv::Vec4i> lines;
  cv::HoughLinesP(centres, lines, 1.0, kDegToRad, options.hough_votes,
                  options.hough_min_length_cells, options.hough_max_gap_cells);
  std::vector<RidgeSegment> segments;
  segments.reserve(lines.size());
  for (const cv::Vec4i& l : lines) {
    segments.push_back({Eigen::Vector2d(l[0], l[1]), Eigen::Vector2d(l[2], l[3])});
  }
  return segments;
}

namespace {

// Merges b into a when collinear and close enough; returns true if merged.
bool TryMerge(RidgeSegment* a, const RidgeSegment& b, const RidgeSegmentOptions& options) {
  const Eigen::Vector2d d = (a->b_cell - a->a_cell).normalized();
  const Eigen::Vector2d db = (b.b_cell - b.a_cell).normalized();
  if (std::abs(d.dot(db)) < std::cos(options.merge_angle_deg * kDegToRad)) return false;
  const Eigen::Vector2d n(-d.y(), d.x());
  if (std::abs(n.dot(b.a_cell - a->a_cell)) > options.merge_offset_cells ||
      std::abs(n.dot(b.b_cell - a->a_cell)) > options.merge_offset_cells) {
    return false;
  }
  const double a1 = (a->b_cell - a->a_cell).dot(d);
  double s0 = d.dot(b.a_cell - a->a_cell), s1 = d.dot(b.b_cell - a->a_cell);
  if (s0 > s1) std::swap(s0, s1);
  const double gap = std::max(s0 - a1, -s1);
  if (gap > options.merge_gap_cells) return false;
  const Eigen::Vector2d origin = a->a_cell;
  a->a_cell = origin + std::min(0.0, s0) * d;
  a->b_cell = origin + std::max(a1, s1) * d;
  return true;
}

}  // namespace

std::vector<RidgeSegment> MergeCollinearSegments(std::vector<RidgeSegment> segments,
                                                 const RidgeSegmentOptions& options) {
  bool merged_any = true;
  while (merged_any) {
    merged_any = false;
    std::stable_sort(
        segments.begin(), segments.end(),
        [](const RidgeSegment& x, const RidgeSegment& y) { return x.Length() > y.Length(); });
    std::vector<RidgeSegment> out;
    for (const RidgeSegment& s : segments) {
      bool merged = false;
      for (RidgeSegment& o : out) {
        if (TryMerge(&o, s, options)) {
          merged = merged_any = true;
          break;
        }
      }
      if (!merged) out.push_back(s);
    }
    segments = std::move(out);
  }
  return segments;
}

}  // namespace groundline::perception
