// The verdict on an intrinsic calibration and its report files.
//
// PASS when every rule below holds (each rule's threshold is a field of
// ReportThresholds, read from the config's `intrinsics_report:`), over the
// inliers (conventions of intrinsic_calibration.h):
//   views      at least min_views views (the guide asks for 20-40);
//   rms_px     <= max_rms_px     (per point: sqrt(mean |r|^2));
//   worst_px   <= max_worst_px   (largest |r|);
//   quadrants  each image quadrant holds >= min_corners_per_quadrant corners
//              (require_all_quadrants);
//   border     each of the 8 zones of the imager's outer ring (4 corners, 4
//              edges; the ring is border_fraction of the width and height
//              deep) holds >= min_corners_per_border_zone corners
//              (require_border_coverage): the distortion is largest there and
//              only corners there constrain it;
//   tilt       some view's board is tilted >= min_tilt_deg about the camera's
//              vertical axis and some about its horizontal axis (solved board
//              poses): tilt separates the focal length from the distance;
//   uncertainty the worst 1-sigma projection uncertainty
//              (projection_uncertainty.h) at uncertainty_range_m over the
//              part of the imager that sees the floor (rows below
//              floor_top_fraction of the height) <= max_projection_uncertainty_px;
//   live       the live guidance found the coverage complete (a live session
//              that stopped early passes its "still missing" lines in; each
//              becomes a failure, so the live verdict and the report agree).
// Every failure comes with advice saying what to capture or do next.
//
// Files: report.json (every figure, per-image table, thresholds, verdict) and
// report.html (self-contained: inline SVG plots of the residual vector field,
// the residual histogram, the corner coverage heatmap with quadrant counts,
// the projection-uncertainty heatmap, and the per-image table). Both written
// atomically.
#ifndef GROUNDLINE_CALIBRATION_CALIBRATION_REPORT_H_
#define GROUNDLINE_CALIBRATION_CALIBRATION_REPORT_H_

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "groundline/calibration/intrinsic_calibration.h"
#include "groundline/calibration/projection_uncertainty.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct ReportThresholds {
  int min_views = 20;
  double max_rms_px = 0.5;
  double max_worst_px = 2.0;
  bool require_all_quadrants = true;
  int min_corners_per_quadrant = 10;
  bool require_border_coverage = true;
  double border_fraction = 0.1;
  int min_corners_per_border_zone = 5;
  double min_tilt_deg = 20.0;
  double max_projection_uncertainty_px = 0.25;
  double uncertainty_range_m = 2.0;
  double floor_top_fraction = 0.0;  // 0: the whole imager sees the floor
  core::Status Validate() const;
};

// Reads the optional `intrinsics_report:` mapping of a YAML config
// (one key per ReportThresholds field, same names); absent keys keep their
// defaults. Errors name the file and the key.
core::Result<ReportThresholds> ReadReportThresholds(const std::filesystem::path& path);

// An image given to the calibration that did not become a view.
struct RejectedImage {
  std::string name;
  std::string reason;
};

// The projection uncertainty's worst figure over the floor part of the
// imager at one range.
struct UncertaintyFigure {
  double range_m = 0.0;
  double worst_px = 0.0;
  double worst_mm = 0.0;                               // projection_uncertainty.h: lateral, face on
  Eigen::Vector2d where_px = Eigen::Vector2d::Zero();  // cell centre of the worst
  // Cells where it cannot be computed (the solved lens model does not
  // unproject there: it folds back where no corner constrained it); they fail
  // the rule. first_not_computable_px: the first such cell's centre.
  int cells_not_computable = 0;
  Eigen::Vector2d first_not_computable_px = Eigen::Vector2d::Zero();
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
  // Inlier corners in the outer ring's zones: top-left, top, top-right, left,
  // right, bottom-left, bottom, bottom-right.
  std::array<int, 8> border_corners{};
  double max_tilt_about_vertical_deg = 0.0;
  double max_tilt_about_horizontal_deg = 0.0;
  // Worst figures at 1, 2 and 4 m and at uncertainty_range_m (last), and the
  // maps at the same ranges (uncertainty_map: the last); empty when the
  // calibration has no covariance. report.json carries the 2x2 covariance
  // of every map cell, which the commissioning report carries to the floor.
  std::vector<UncertaintyFigure> uncertainty;
  std::vector<UncertaintyMap> uncertainty_maps;
  UncertaintyMap uncertainty_map;
  double observed_pixel_sigma_px = 0.0;
  std::vector<std::string> live_missing;  // as given
  std::string camera_fingerprint;         // CameraFingerprint of the solved camera
};

// live_missing: what a live session's guidance still asked for when it
// stopped (ViewCoverage::Missing()); empty for a folder run or a complete
// live session.
CalibrationReport BuildCalibrationReport(const IntrinsicCalibration& calibration,
                                         const std::string& target_name,
                                         std::vector<RejectedImage> rejected,
                                         const ReportThresholds& thresholds,
                                         std::vector<std::string> live_missing = {});

// A short hash (16 hex digits, FNV-1a 64) of what makes a camera model: lens
// model name, imager size and every intrinsic parameter bit for bit. The
// intrinsics report states it; a combined commissioning report checks that
// the floor calibration used the same camera.
std::string CameraFingerprint(const CameraModel& camera);

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
