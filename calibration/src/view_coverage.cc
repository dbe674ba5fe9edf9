#include "groundline/calibration/view_coverage.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "groundline/core/angles.h"
#include "imager_zones.h"

namespace groundline::calibration {
namespace {

using core::kRadToDeg;
constexpr const char* kRegionNames[9] = {"top-left",    "top",    "top-right",
                                         "left",        "centre", "right",
                                         "bottom-left", "bottom", "bottom-right"};

double Median(std::vector<double> v) {
  assert(!v.empty());
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Mean corner motion between two views over their shared grid points, px;
// infinity when they share fewer than half the corners of `a`.
double MeanSharedMotion(const BoardObservation& a, const BoardObservation& b) {
  double sum = 0.0;
  int shared = 0;
  for (std::size_t i = 0; i < a.grid_index.size(); ++i) {
    const auto it = std::find(b.grid_index.begin(), b.grid_index.end(), a.grid_index[i]);
    if (it == b.grid_index.end()) continue;
    sum += (a.corners_px[i] - b.corners_px[it - b.grid_index.begin()]).norm();
    ++shared;
  }
  if (shared == 0 || 2 * shared < static_cast<int>(a.grid_index.size())) {
    return std::numeric_limits<double>::infinity();
  }
  return sum / shared;
}

}  // namespace

core::Status ViewCoverageOptions::Validate() const {
  if (min_views < 3) return core::Status::Error("ViewCoverageOptions: min_views must be >= 3");
  if (!(border_fraction > 0.0 && border_fraction < 0.5)) {
    return core::Status::Error("ViewCoverageOptions: border_fraction must be in (0, 0.5)");
  }
  if (min_corners_per_region < 0 || min_corners_per_border_zone < 0 || novelty_cells_x < 1 ||
      novelty_cells_y < 1) {
    return core::Status::Error("ViewCoverageOptions: counts must be >= 0 and cells >= 1");
  }
  if (!(min_tilt_deg >= 0.0 && min_tilt_deg < 80.0) || !(tilt_bin_deg > 0.0) ||
      !(assumed_hfov_deg > 5.0 && assumed_hfov_deg < 170.0)) {
    return core::Status::Error(
        "ViewCoverageOptions: tilts in [0, 80) deg, bins > 0, field of view in (5, 170) deg");
  }
  if (!(min_distance_ratio >= 1.0) || !(distance_bin_ratio > 1.0) ||
      !(duplicate_motion_fraction >= 0.0) || !(duplicate_tilt_deg >= 0.0) ||
      !(min_sharpness_ratio >= 0.0)) {
    return core::Status::Error(
        "ViewCoverageOptions: distance ratios >= 1 (bins > 1), duplicate and sharpness >= 0");
  }
  return core::Status::Ok();
}

core::Result<RoughBoardPose> EstimateRoughBoardPose(const BoardObservation& observation,
                                                    const BoardGrid& grid, int width_px,
                                                    int height_px, double assumed_hfov_deg) {
  if (observation.corners_px.size() < 4) {
    return core::Status::Error("fewer than 4 corners: no board pose");
  }
  std::vector<cv::Point2d> board, image;
  Eigen::Vector3d centre_board = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < observation.corners_px.size(); ++i) {
    const Eigen::Vector3d p = grid.Point_board(observation.grid_index[i]);
    centre_board += p;
    board.emplace_back(p.x(), p.y());
    image.emplace_back(observation.corners_px[i].x(), observation.corners_px[i].y());
  }
  centre_board /= static_cast<double>(board.size());
  const cv::Mat H_cv = cv::findHomography(board, image, 0);
  if (H_cv.empty()) return core::Status::Error("degenerate corners: no board homography");
  Eigen::Matrix3d H;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) H(r, c) = H_cv.at<double>(r, c);
  }
  const double f = 0.5 * width_px / std::tan(0.5 * assumed_hfov_deg / kRadToDeg);
  Eigen::Matrix3d K;
  K << f, 0, 0.5 * (width_px - 1), 0, f, 0.5 * (height_px - 1), 0, 0, 1;
  const Eigen::Matrix3d M = K.inverse() * H;
  double scale = 1.0 / M.col(0).norm();
  if (M(2, 2) * scale < 0.0) scale = -scale;  // the board in front of the camera
  const Eigen::Vector3d r1 = (scale * M.col(0)).normalized();
  const Eigen::Vector3d r2 = scale * M.col(1) / (scale * M.col(1)).norm();
  const Eigen::Vector3d r3 = r1.cross(r2).normalized();
  const Eigen::Vector3d t = scale * M.col(2);
  Eigen::Matrix3d R;
  R << r1, r2, r3;
  RoughBoardPose pose;
  pose.tilt_about_vertical_deg = std::atan2(r3.x(), r3.z()) * kRadToDeg;
  pose.tilt_about_horizontal_deg = std::atan2(r3.y(), r3.z()) * kRadToDeg;
  pose.distance_m = (R * centre_board + t).norm();
  if (!std::isfinite(pose.distance_m) || !(pose.distance_m > 0.0)) {
    return core::Status::Error("degenerate board homography");
  }
  return pose;
}

double BoardSharpness(const cv::Mat& grey, const BoardObservation& observation) {
  assert(grey.type() == CV_8UC1);
  constexpr int kHalf = 5;
  std::vector<double> values;
  for (const Eigen::Vector2d& q : observation.corners_px) {
    const int u = static_cast<int>(std::lround(q.x())), v = static_cast<int>(std::lround(q.y()));
    if (u - kHalf - 1 < 0 || v - kHalf - 1 < 0 || u + kHalf + 1 >= grey.cols ||
        v + kHalf + 1 >= grey.rows) {
      continue;
    }
    const cv::Mat patch =
        grey(cv::Rect(u - kHalf - 1, v - kHalf - 1, 2 * kHalf + 3, 2 * kHalf + 3));
    cv::Mat gx, gy, magnitude;
    cv::Sobel(patch, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
    cv::Sobel(patch, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
    cv::magnitude(gx, gy, magnitude);
    const cv::Rect inner(1, 1, 2 * kHalf + 1, 2 * kHalf + 1);
    double max_gradient = 0.0, lo = 0.0, hi = 0.0;
    cv::minMaxLoc(magnitude(inner), nullptr, &max_gradient);
    cv::minMaxLoc(patch(inner), &lo, &hi);
    if (hi - lo >= 16.0) values.push_back(max_gradient / (hi - lo));
  }
  return values.empty() ? 0.0 : Median(values);
}

ViewCoverage::ViewCoverage(const BoardGrid& grid, int width_px, int height_px,
                           const ViewCoverageOptions& options)
    : grid_(grid), width_px_(width_px), height_px_(height_px), options_(options) {
  assert(options.Validate().ok() && width_px > 0 && height_px > 0);
}

int ViewCoverage::Region(const Eigen::Vector2d& q) const {
  const int x = std::clamp(static_cast<int>(3.0 * q.x() / width_px_), 0, 2);
  const int y = std::clamp(static_cast<int>(3.0 * q.y() / height_px_), 0, 2);
  return 3 * y + x;
}

int ViewCoverage::NoveltyCell(const Eigen::Vector2d& q) const {
  const int x = std::clamp(static_cast<int>(options_.novelty_cells_x * q.x() / width_px_), 0,
                           options_.novelty_cells_x - 1);
  const int y = std::clamp(static_cast<int>(options_.novelty_cells_y * q.y() / height_px_), 0,
                           options_.novelty_cells_y - 1);
  return y * options_.novelty_cells_x + x;
}

ViewVerdict ViewCoverage::Consider(const BoardObservation& observation, double sharpness) {
  core::Result<RoughBoardPose> pose =
      EstimateRoughBoardPose(observation, grid_, width_px_, height_px_, options_.assumed_hfov_deg);
  if (!pose.ok()) return {ViewDecision::kNoPose, pose.message()};
  char text[200];
  if (views_.size() >= 3) {
    std::vector<double> kept;
    for (const KeptView& v : views_) kept.push_back(v.sharpness);
    const double median = Median(kept);
    if (sharpness < options_.min_sharpness_ratio * median) {
      std::snprintf(text, sizeof(text),
                    "blurred (sharpness %.2f, kept views %.2f): hold the board still", sharpness,
                    median);
      return {ViewDecision::kBlurred, text};
    }
  }
  const double diagonal_px = std::hypot(width_px_, height_px_);
  for (std::size_t k = 0; k < views_.size(); ++k) {
    const double motion_px = MeanSharedMotion(observation, views_[k].observation);
    const RoughBoardPose& kept = views_[k].pose;
    if (motion_px < options_.duplicate_motion_fraction * diagonal_px &&
        std::abs(pose->tilt_about_vertical_deg - kept.tilt_about_vertical_deg) <
            options_.duplicate_tilt_deg &&
        std::abs(pose->tilt_about_horizontal_deg - kept.tilt_about_horizontal_deg) <
            options_.duplicate_tilt_deg) {
      std::snprintf(text, sizeof(text),
                    "near-duplicate of view %zu (corners moved %.1f px): move or tilt the board",
                    k + 1, motion_px);
      return {ViewDecision::kDuplicate, text};
    }
  }
  std::set<int> cells;
  for (const Eigen::Vector2d& q : observation.corners_px) cells.insert(NoveltyCell(q));
  int new_cells = 0;
  for (int c : cells) new_cells += cells_.count(c) == 0 ? 1 : 0;
  const std::pair<int, int> tilt_bin = {
      static_cast<int>(std::lround(pose->tilt_about_vertical_deg / options_.tilt_bin_deg)),
      static_cast<int>(std::lround(pose->tilt_about_horizontal_deg / options_.tilt_bin_deg))};
  const int distance_bin = static_cast<int>(
      std::floor(std::log(pose->distance_m) / std::log(options_.distance_bin_ratio)));
  const bool new_tilt = tilt_bins_.count(tilt_bin) == 0;
  const bool new_distance = distance_bins_.count(distance_bin) == 0;
  if (new_cells == 0 && !new_tilt && !new_distance) {
    return {ViewDecision::kNothingNew,
            "adds no new image area, tilt or distance: move the board somewhere new"};
  }
  cells_.insert(cells.begin(), cells.end());
  tilt_bins_.insert(tilt_bin);
  distance_bins_.insert(distance_bin);
  for (const Eigen::Vector2d& q : observation.corners_px) {
    ++region_corners_[Region(q)];
    const int zone = internal::BorderZone(q, width_px_, height_px_, options_.border_fraction);
    if (zone >= 0) ++border_corners_[zone];
  }
  views_.push_back({observation, *pose, sharpness});
  std::snprintf(text, sizeof(text),
                "kept: %d new image cells, tilt %+.0f/%+.0f deg (vertical/horizontal axis), "
                "distance %.2f",
                new_cells, pose->tilt_about_vertical_deg, pose->tilt_about_horizontal_deg,
                pose->distance_m);
  return {ViewDecision::kKept, text};
}

std::vector<std::string> ViewCoverage::Missing() const {
  std::vector<std::string> missing;
  char text[200];
  std::string regions;
  for (int r = 0; r < 9; ++r) {
    if (region_corners_[r] < options_.min_corners_per_region) {
      std::snprintf(text, sizeof(text), "%s%s (%d of %d corners)", regions.empty() ? "" : ", ",
                    kRegionNames[r], region_corners_[r], options_.min_corners_per_region);
      regions += text;
    }
  }
  if (!regions.empty()) missing.push_back("hold the board in the image's " + regions);
  std::string zones;
  for (int z = 0; z < 8; ++z) {
    if (border_corners_[z] < options_.min_corners_per_border_zone) {
      std::snprintf(text, sizeof(text), "%s%s (%d of %d)", zones.empty() ? "" : ", ",
                    internal::kBorderZoneNames[z], border_corners_[z],
                    options_.min_corners_per_border_zone);
      zones += text;
    }
  }
  if (!zones.empty()) {
    std::snprintf(text, sizeof(text), "push the board's corners to within %.0f%% of the image's ",
                  100.0 * options_.border_fraction);
    missing.push_back(text + zones);
  }
  double max_vertical = 0.0, max_horizontal = 0.0;
  double near_m = std::numeric_limits<double>::infinity(), far_m = 0.0;
  for (const KeptView& v : views_) {
    max_vertical = std::max(max_vertical, std::abs(v.pose.tilt_about_vertical_deg));
    max_horizontal = std::max(max_horizontal, std::abs(v.pose.tilt_about_horizontal_deg));
    near_m = std::min(near_m, v.pose.distance_m);
    far_m = std::max(far_m, v.pose.distance_m);
  }
  if (max_vertical < options_.min_tilt_deg) {
    std::snprintf(text, sizeof(text),
                  "tilt the board about its vertical axis: left or right edge 30-45 deg away "
                  "(most so far %.0f deg, need %.0f)",
                  max_vertical, options_.min_tilt_deg);
    missing.push_back(text);
  }
  if (max_horizontal < options_.min_tilt_deg) {
    std::snprintf(text, sizeof(text),
                  "tilt the board about its horizontal axis: top or bottom edge 30-45 deg away "
                  "(most so far %.0f deg, need %.0f)",
                  max_horizontal, options_.min_tilt_deg);
    missing.push_back(text);
  }
  const double ratio = views_.empty() ? 1.0 : far_m / near_m;
  if (ratio < options_.min_distance_ratio) {
    std::snprintf(text, sizeof(text),
                  "vary the distance: hold the board nearer and farther (range so far x%.2f, "
                  "need x%.2f)",
                  ratio, options_.min_distance_ratio);
    missing.push_back(text);
  }
  if (views() < options_.min_views) {
    std::snprintf(text, sizeof(text), "%d more view(s) needed", options_.min_views - views());
    missing.push_back(text);
  }
  return missing;
}

std::string ViewCoverage::StatusLine() const {
  int covered = 0;
  for (int c : region_corners_) covered += c >= options_.min_corners_per_region ? 1 : 0;
  return std::to_string(views()) + " of " + std::to_string(options_.min_views) +
         " views; image regions covered " + std::to_string(covered) + " of 9" +
         (Complete() ? "; coverage complete" : "");
}

}  // namespace groundline::calibration
