// What a set of calibration views still lacks, for the live intrinsic
// calibration (`groundline calibrate intrinsics --live`): which view to keep,
// and what to tell the technician holding the board.
//
// A candidate view (the board's detected corners) is judged in this order:
//   blurred    its BoardSharpness is below min_sharpness_ratio times the
//              median of the kept views (judged once 3 views are kept);
//   duplicate  the corners it shares with a kept view moved on average less
//              than duplicate_motion_fraction of the image diagonal, and its
//              tilts differ from that view's by less than duplicate_tilt_deg
//              (tilting the board in place moves its corners little);
//   nothing new it covers no new cell of a novelty_cells_x x novelty_cells_y
//              grid on the imager, no new (tilt about x, tilt about y) bin of
//              tilt_bin_deg, and no new distance bin (ratio distance_bin_ratio);
//   kept       otherwise.
// Complete() when all of:
//   - at least min_views views;
//   - each of the 3 x 3 image regions (top-left ... bottom-right) holds at
//     least min_corners_per_region corners of the kept views (the corners
//     near the border constrain the distortion: mrcal's and OpenCV's advice);
//   - each of the 8 zones of the imager's outer ring (border_fraction deep:
//     4 corners, 4 edges) holds at least min_corners_per_border_zone corners
//     (0: no such rule); the intrinsics report's border rule, with the same
//     zones, so that the guidance asks for what the verdict needs;
//   - some view is tilted >= min_tilt_deg about the board's vertical axis and
//     some about its horizontal axis (tilt separates focal length from
//     distance);
//   - the board distances span a ratio >= min_distance_ratio.
// Tilt and distance come from RoughBoardPose: the homography board -> image
// decomposed with a pinhole guess (focal length from assumed_hfov_deg, centre
// at the image centre). They are rough (a wrong focal guess scales the
// distance and bends the tilt by a few degrees), enough to tell a flat view
// from a tilted one and near from far.
//
// Pure: no I/O, no clock. Not thread-safe (one per live session).
#ifndef GROUNDLINE_CALIBRATION_VIEW_COVERAGE_H_
#define GROUNDLINE_CALIBRATION_VIEW_COVERAGE_H_

#include <array>
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "groundline/calibration/board_detection.h"
#include "groundline/calibration/calib_target.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct ViewCoverageOptions {
  int min_views = 12;
  int min_corners_per_region = 10;
  double border_fraction = 0.1;         // as ReportThresholds
  int min_corners_per_border_zone = 5;  // as ReportThresholds; 0: off
  double min_tilt_deg = 20.0;
  double min_distance_ratio = 1.3;
  double duplicate_motion_fraction = 0.02;
  double duplicate_tilt_deg = 5.0;
  double min_sharpness_ratio = 0.5;
  int novelty_cells_x = 8;
  int novelty_cells_y = 6;
  double tilt_bin_deg = 10.0;
  double distance_bin_ratio = 1.15;
  double assumed_hfov_deg = 60.0;
  core::Status Validate() const;
};

// Board pose from one view with a guessed pinhole (file comment).
struct RoughBoardPose {
  // Rotation of the board's normal about the camera's y axis (down: the
  // board's left or right edge turned away) and about its x axis (the top or
  // bottom edge turned away), degrees; 0 for a board facing the camera.
  double tilt_about_vertical_deg = 0.0;
  double tilt_about_horizontal_deg = 0.0;
  double distance_m = 0.0;  // camera to the board's centre, in the guess's scale
};

// Fails for fewer than 4 corners or a degenerate homography.
core::Result<RoughBoardPose> EstimateRoughBoardPose(const BoardObservation& observation,
                                                    const BoardGrid& grid, int width_px,
                                                    int height_px, double assumed_hfov_deg);

// Median over the corners of max |gradient| / (max - min intensity) in a
// 11 x 11 px window around each corner, 1/px: about 0.5 for a sharp edge,
// 0.4 / sigma_px for an edge blurred by a Gaussian of sigma_px > 1.
// grey: 8-bit, 1 channel. 0 when no corner is inside the image.
double BoardSharpness(const cv::Mat& grey, const BoardObservation& observation);

enum class ViewDecision { kKept, kBlurred, kDuplicate, kNothingNew, kNoPose };

struct ViewVerdict {
  ViewDecision decision = ViewDecision::kKept;
  std::string reason;  // why it was rejected, or what it added
};

class ViewCoverage {
 public:
  // options must be valid (asserted).
  ViewCoverage(const BoardGrid& grid, int width_px, int height_px,
               const ViewCoverageOptions& options);

  // Judges a view (file comment) and keeps it when kKept.
  ViewVerdict Consider(const BoardObservation& observation, double sharpness);

  int views() const { return static_cast<int>(views_.size()); }
  bool Complete() const { return Missing().empty(); }
  // What is still missing, one instruction per line, e.g.
  //   "hold the board in the image's top-left (3 of 10 corners), left (0 of 10 corners)"
  //   "tilt the board about its vertical axis (left or right edge 30-45 deg away)"
  // Empty when Complete().
  std::vector<std::string> Missing() const;
  // "7 of 12 views; image regions covered 6 of 9", with "; coverage
  // complete" appended when Complete().
  std::string StatusLine() const;
  // Corners of the kept views in each region, row-major from the top-left.
  const std::array<int, 9>& region_corners() const { return region_corners_; }

 private:
  struct KeptView {
    BoardObservation observation;
    RoughBoardPose pose;
    double sharpness;
  };
  int Region(const Eigen::Vector2d& q) const;
  int NoveltyCell(const Eigen::Vector2d& q) const;

  BoardGrid grid_;
  int width_px_, height_px_;
  ViewCoverageOptions options_;
  std::vector<KeptView> views_;
  std::array<int, 9> region_corners_{};
  std::array<int, 8> border_corners_{};
  std::set<int> cells_;
  std::set<std::pair<int, int>> tilt_bins_;
  std::set<int> distance_bins_;
};

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_VIEW_COVERAGE_H_
