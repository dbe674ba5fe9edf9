#include "groundline/calibration/board_detection.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace groundline::calibration {

TagDetectorOptions BoardTagDetectorOptions() {
  TagDetectorOptions options;
  options.quad_decimate = 1.0;
  options.quad_sigma = 0.0;
  options.refine_edges = false;
  options.max_bits_corrected = 0;
  options.min_decision_margin = 0.0;
  options.border_margin_px = 0.0;
  options.one_per_id = false;  // an id seen twice is ambiguous: DetectAprilGrid skips it
  return options;
}

std::vector<TagDetection> DetectTags(const cv::Mat& gray, const TagDetectorOptions& options) {
  assert(gray.type() == CV_8UC1);
  return DetectTags(gray.data, gray.cols, gray.rows, static_cast<int>(gray.step[0]), options);
}

core::Status BoardDetectionOptions::Validate() const {
  if (core::Status s = apriltag.Validate(); !s.ok()) return s;
  if (chessboard_subpix_half_window_px < 0) {
    return core::Status::Error("chessboard_subpix_half_window_px must be >= 0 (0: automatic)");
  }
  if (!(chessboard_subpix_epsilon_px > 0.0) || chessboard_subpix_iterations < 1) {
    return core::Status::Error("cornerSubPix needs an epsilon > 0 and >= 1 iteration");
  }
  if (min_aprilgrid_tags < 1) return core::Status::Error("min_aprilgrid_tags must be >= 1");
  return core::Status::Ok();
}

namespace {

core::Result<BoardObservation> DetectChessboard(const cv::Mat& gray, const CalibTarget& target,
                                                const BoardGrid& grid,
                                                const BoardDetectionOptions& options) {
  const cv::Size pattern(target.inner_corners_x, target.inner_corners_y);
  std::vector<cv::Point2f> corners;
  const bool found = cv::findChessboardCorners(
      gray, pattern, corners,
      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_FAST_CHECK | cv::CALIB_CB_NORMALIZE_IMAGE);
  if (!found) {
    return core::Status::Error("chessboard " + std::to_string(pattern.width) + "x" +
                               std::to_string(pattern.height) +
                               " inner corners not found (the whole board must be in view)");
  }
  int w = options.chessboard_subpix_half_window_px;
  if (w == 0) {
    double spacing = std::numeric_limits<double>::infinity();
    for (int y = 0; y < pattern.height; ++y) {
      for (int x = 0; x < pattern.width; ++x) {
        const cv::Point2f& c = corners[y * pattern.width + x];
        if (x + 1 < pattern.width)
          spacing = std::min<double>(spacing, cv::norm(corners[y * pattern.width + x + 1] - c));
        if (y + 1 < pattern.height)
          spacing = std::min<double>(spacing, cv::norm(corners[(y + 1) * pattern.width + x] - c));
      }
    }
    w = std::clamp(static_cast<int>(spacing / 4.0), 2, 11);
  }
  cv::cornerSubPix(
      gray, corners, cv::Size(w, w), cv::Size(-1, -1),
      cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT,
                       options.chessboard_subpix_iterations, options.chessboard_subpix_epsilon_px));
  BoardObservation obs;
  obs.grid_index = grid.observable;
  for (const cv::Point2f& c : corners) obs.corners_px.emplace_back(c.x, c.y);
  return obs;
}

core::Result<BoardObservation> DetectAprilGrid(const cv::Mat& gray, const CalibTarget& target,
                                               const BoardGrid& grid,
                                               const BoardDetectionOptions& options) {
  const std::vector<TagDetection> tags = DetectTags(gray, options.apriltag);
  BoardObservation obs;
  int used = 0;
  int previous_id = -1;
  for (const TagDetection& tag : tags) {
    // A board id seen twice is ambiguous (another board in view): skip both.
    const bool duplicate = std::count_if(tags.begin(), tags.end(),
                                         [&](const TagDetection& t) { return t.id == tag.id; }) > 1;
    if (duplicate || tag.id == previous_id) continue;
    previous_id = tag.id;
    if (AprilGridCornerIndex(target, grid, tag.id, 0) < 0) continue;
    for (int k = 0; k < 4; ++k) {
      obs.grid_index.push_back(AprilGridCornerIndex(target, grid, tag.id, k));
      obs.corners_px.push_back(tag.corners_px[k]);
    }
    ++used;
  }
  if (used < options.min_aprilgrid_tags) {
    return core::Status::Error("aprilgrid: " + std::to_string(used) + " board tag(s) found, " +
                               std::to_string(options.min_aprilgrid_tags) + " needed");
  }
  return obs;
}

}  // namespace

core::Result<BoardObservation> DetectBoard(const cv::Mat& image, const CalibTarget& target,
                                           const BoardGrid& grid,
                                           const BoardDetectionOptions& options) {
  assert(target.IsBoard() && options.Validate().ok());
  cv::Mat gray;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  } else {
    gray = image;
  }
  if (gray.depth() != CV_8U) return core::Status::Error("expected an 8-bit image");
  if (target.type == TargetType::kChessboard) return DetectChessboard(gray, target, grid, options);
  return DetectAprilGrid(gray, target, grid, options);
}

}  // namespace groundline::calibration
