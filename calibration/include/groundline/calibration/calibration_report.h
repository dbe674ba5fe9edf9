// The verdict on an intrinsic calibration and its report files.
//
// PASS when, over the inliers (conventions of intrinsic_calibration.h):
//   rms_px   <= max_rms_px     (default 0.5 px, per point: sqrt(mean |r|^2))
//   worst_px <= max_worst_px   (default 2 px, largest |r|)
//   each image quadrant (split at the imager centre) holds at least
//   min_corners_per_quadrant inlier corners (default 10), unless
//   require_all_quadrants is false.
// A failure comes with advice saying what to do next: which image to drop or
// retake, which region of the image needs more views.
//
// Files: report.json (every figure, per-image table, thresholds, verdict) and
// report.html (self-contained: inline SVG plots of the residual vector field,
// the residual histogram, the corner coverage heatmap with quadrant counts,
// and the per-image table). Both written atomically.
#ifndef GROUNDLINE_CALIBRATION_CALIBRATION_REPORT_H_
#define GROUNDLINE_CALIBRATION_CALIBRATION_REPORT_H_

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "groundline/calibration/intrinsic_calibration.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct ReportThresholds {
  double max_rms_px = 0.5;
  double max_worst_px = 2.0;
  bool require_all_quadrants = true;
  int min_corners_per_quadrant = 10;
  core::Status Validate() const;
};

// Reads the optional `intrinsics_report:` mapping of a YAML config
// (max_rms_px, max_worst_px, require_all_quadrants, min_corners_per_quadrant);
// absent keys keep their defaults. Errors name the file and the key.
core::Result<ReportThresholds> ReadReportThresholds(const std::filesystem::path& path);

// An image given to the calibration that did not become a view.
struct RejectedImage {
  std::string name;
  std::string reason;
};

struct CalibrationReport {
  std::string target_name;
  ReportThresholds thresholds;
  bool pass = false;
  std::vector<std::string> failures;  // one line per failed criterion
  std::vector<std::string> advice;    // what to do next
  // Inlier corners per quadrant: top-left, top-right, bottom-left, bottom-right.
  std::array<int, 4> quadrant_corners{};
  static constexpr int kCoverageCellsX = 16;
  static constexpr int kCoverageCellsY = 12;
  std::vector<int> coverage;      // kCoverageCellsY x kCoverageCellsX, row-major, inlier corners
  std::vector<int> views_by_rms;  // view indices, worst RMS first
  std::vector<RejectedImage> rejected;
};

CalibrationReport BuildCalibrationReport(const IntrinsicCalibration& calibration,
                                         const std::string& target_name,
                                         std::vector<RejectedImage> rejected,
                                         const ReportThresholds& thresholds);

std::string CalibrationReportJson(const CalibrationReport& report,
                                  const IntrinsicCalibration& calibration);
std::string CalibrationReportHtml(const CalibrationReport& report,
                                  const IntrinsicCalibration& calibration);

// Writes into out_dir (created if missing), each file atomically:
//   camera.cameramodel   mrcal (full precision; mrcal's tools read it)
//   camera_opencv.yaml   OpenCV calibration file (OPENCV and PINHOLE models)
//   camera_info.yaml     ROS camera_info (PINHOLE, OPENCV4, OPENCV5, OPENCV8)
//   report.json, report.html
core::Status WriteCalibrationOutputs(const std::filesystem::path& out_dir,
                                     const CalibrationReport& report,
                                     const IntrinsicCalibration& calibration);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_CALIBRATION_REPORT_H_
