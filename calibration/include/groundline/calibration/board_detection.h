// Corner detection in calibration images.
//
// AprilTags (tag36h11) through libapriltag: DetectAprilTags. Corners are in
// pixels, (u, v) = (column, row), integer values at pixel centres (the
// convention of camera_model.h, OpenCV and mrcal). libapriltag's own
// coordinates put pixel centres at +0.5 (its pixel i spans [i, i + 1]); the
// 0.5 px is subtracted here (measured: on rendered sheets its raw corners sit
// 0.500 px right of and below the true ones). Corner order is libapriltag's:
// counter-clockwise in the image starting at the tag's bottom-left
// (bottom-left, bottom-right, top-right, top-left of an upright tag).
// Debian's libapriltag 3.3 has a corner bias when quad_decimate > 1, so
// calibration uses 1 (the default). Corners are the intersections of the
// quad's sub-pixel line fits; refine_edges (off by default) moves them along
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
// DetectAprilTags, each contributing its four corners.
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
#include "groundline/core/status.h"

namespace groundline::calibration {

struct AprilTagOptions {
  float quad_decimate = 1.0f;  // 1: full resolution (no decimation bias)
  float quad_sigma = 0.0f;     // Gaussian blur before quad detection, px
  bool refine_edges = false;
  int max_hamming = 0;  // bits corrected; 0 keeps false positives out of calibrations
  int threads = 1;
  core::Status Validate() const;
};

struct TagDetection {
  int id = -1;
  std::array<Eigen::Vector2d, 4> corners_px;  // see the file comment for the order
  int hamming = 0;
  double decision_margin = 0.0;
};

// Detections in an 8-bit single-channel image, sorted by id, then by the
// corners' mean u, then v. Options must be valid (asserted).
std::vector<TagDetection> DetectAprilTags(const cv::Mat& gray, const AprilTagOptions& options);

struct BoardDetectionOptions {
  AprilTagOptions apriltag;
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
