// Corner detection in calibration images.
//
// AprilTags (tag36h11) through libapriltag, the one adapter of
// tag_detection.h (pixel convention and corner order are documented there:
// libapriltag's +0.5 px pixel centres removed, measured 0.500 px on rendered
// sheets). Debian's libapriltag 3.3 has a corner bias when quad_decimate > 1,
// so calibration uses 1. Corners are the intersections of the quad's
// sub-pixel line fits; refine_edges (off by default) moves them along
// the image gradient, which on rendered test sheets made them worse (0.24 px
// worst against 0.02 px), and cv::cornerSubPix on the tag's L-corners was
// biased by blur (0.22 px at sigma 1.5 px), so neither is used by default.
//
// Boards (calib_target.h): DetectBoard returns the corners of one view with
// their grid indices (BoardGrid). Chessboards: OpenCV findChessboardCorners
// (adaptive threshold, normalized image, fast check) then cornerSubPix with
// a (2w+1)^2 window: w = chessboard_subpix_half_window_px, or when that is 0
// (the default) a quarter of the smallest spacing between neighbouring
// corners in the view, clamped to [2, 11] px: a window reaching the next
// corner biases the fit (on OpenCV's 640x480 set, w = 11 gives a 0.41 px RMS
// calibration, w = 6 about 0.19 px). OpenCV's calibration sample, which made
// the published reference there, used w = 11 and a 0.1 px stop criterion.
// AprilGrids: every tag of the board's id range found by
// DetectTags, each contributing its four corners.
//
// Thread-safety: functions are reentrant (each call creates its own detector).
#ifndef GROUNDLINE_CALIBRATION_BOARD_DETECTION_H_
#define GROUNDLINE_CALIBRATION_BOARD_DETECTION_H_

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/tag_detection.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

// The detector settings for calibration boards: full resolution, libapriltag's
// line-fit corners (no edge refinement: see the file comment), no corrected
// bits (false positives must stay out of a calibration), no margin or border
// filter (the board's own id range and the solver's outlier rejection decide).
TagDetectorOptions BoardTagDetectorOptions();

// DetectTags (tag_detection.h) on an 8-bit single-channel cv::Mat.
std::vector<TagDetection> DetectTags(const cv::Mat& gray, const TagDetectorOptions& options);

struct BoardDetectionOptions {
  TagDetectorOptions apriltag = BoardTagDetectorOptions();
  int chessboard_subpix_half_window_px = 0;    // 0: from the corner spacing
  double chessboard_subpix_epsilon_px = 1e-3;  // cornerSubPix stop criterion
  int chessboard_subpix_iterations = 40;
  int min_aprilgrid_tags = 4;  // fewer tags: the view is rejected
  core::Status Validate() const;
};

// One view of a board.
struct BoardObservation {
  std::vector<int> grid_index;              // into BoardGrid (row-major)
  std::vector<Eigen::Vector2d> corners_px;  // same length
};

// Detects the board in an 8-bit image (colour images are converted). Fails,
// saying what was not found, when the board is not seen completely
// (chessboard) or with fewer than min_aprilgrid_tags tags (aprilgrid).
core::Result<BoardObservation> DetectBoard(const cv::Mat& image, const CalibTarget& target,
                                           const BoardGrid& grid,
                                           const BoardDetectionOptions& options);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_BOARD_DETECTION_H_
