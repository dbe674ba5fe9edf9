#include "groundline/perception/floor_texture_flow.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <string>

namespace groundline::perception {

core::Status FloorTextureFlowOptions::Validate() const {
  auto error = [](const std::string& field, const std::string& expected) {
    return core::Status::Error("floor texture flow option '" + field + "': expected " + expected);
  };
  if (max_points < 1) return error("max_points", "at least 1");
  if (!(corner_quality > 0.0 && corner_quality < 1.0))
    return error("corner_quality", "a fraction in (0, 1)");
  if (!(std::isfinite(min_corner_distance_px) && min_corner_distance_px >= 0.0))
    return error("min_corner_distance_px", "a distance >= 0");
  if (window_px < 5 || window_px % 2 == 0) return error("window_px", "an odd size >= 5");
  if (pyramid_levels < 0 || pyramid_levels > 6) return error("pyramid_levels", "0 to 6");
  if (!(std::isfinite(max_forward_backward_px) && max_forward_backward_px > 0.0))
    return error("max_forward_backward_px", "a distance > 0");
  if (margin_px < 0) return error("margin_px", "a distance >= 0");
  return core::Status::Ok();
}

std::vector<FloorTextureMatch> TrackFloorTexture(const cv::Mat& previous,
                                                 const cv::Mat& previous_seen,
                                                 const cv::Mat& current,
                                                 const cv::Mat& current_seen,
                                                 const Eigen::Vector2d& expected_shift_cells,
                                                 const FloorTextureFlowOptions& o) {
  std::vector<FloorTextureMatch> out;
  if (previous.empty() || current.empty() || previous.size() != current.size() ||
      previous.type() != CV_8UC1 || current.type() != CV_8UC1 ||
      previous_seen.size() != previous.size() || current_seen.size() != current.size())
    return out;
  // Corners only where the whole window lies in the seen part of both views
  // (the current view's seen cells shifted back by the expected motion).
  const cv::Mat kernel =
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * o.margin_px + 1, 2 * o.margin_px + 1));
  cv::Mat mask, current_eroded, current_back;
  cv::erode(previous_seen, mask, kernel);
  cv::erode(current_seen, current_eroded, kernel);
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, -expected_shift_cells.x(), 0, 1,
                         -expected_shift_cells.y());
  cv::warpAffine(current_eroded, current_back, shift, current_eroded.size(), cv::INTER_NEAREST,
                 cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::bitwise_and(mask, current_back, mask);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(previous, corners, o.max_points, o.corner_quality,
                          o.min_corner_distance_px, mask);
  if (corners.empty()) return out;
  std::vector<cv::Point2f> tracked(corners.size()), back;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    tracked[i] = corners[i] + cv::Point2f(static_cast<float>(expected_shift_cells.x()),
                                          static_cast<float>(expected_shift_cells.y()));
  }
  std::vector<unsigned char> status, back_status;
  std::vector<float> error, back_error;
  const cv::Size window(o.window_px, o.window_px);
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  cv::calcOpticalFlowPyrLK(previous, current, corners, tracked, status, error, window,
                           o.pyramid_levels, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
  back = corners;
  cv::calcOpticalFlowPyrLK(current, previous, tracked, back, back_status, back_error, window,
                           o.pyramid_levels, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
  const int half = o.window_px / 2;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (!status[i] || !back_status[i]) continue;
    if (std::hypot(back[i].x - corners[i].x, back[i].y - corners[i].y) >
        o.max_forward_backward_px)
      continue;
    const int c = static_cast<int>(std::lround(tracked[i].x));
    const int r = static_cast<int>(std::lround(tracked[i].y));
    if (c < half || r < half || c >= current.cols - half || r >= current.rows - half) continue;
    if (!current_eroded.at<unsigned char>(r, c)) continue;
    out.push_back({Eigen::Vector2d(corners[i].x, corners[i].y),
                   Eigen::Vector2d(tracked[i].x, tracked[i].y)});
  }
  return out;
}

}  // namespace groundline::perception
