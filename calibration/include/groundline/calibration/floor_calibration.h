// Floor commissioning end to end: detect the tags of a layout in a directory
// of images, solve the mount (floor_extrinsics.h), judge it, and report it
// (JSON and a self-contained HTML page with a bird's-eye view of the tag field).
//
// Images. For a floor layout, the images are those of layout.vehicle_poses
// (file names relative to the image directory; a listed file that is missing
// is an error). For a base_link layout, every .png/.pgm/.jpg/.jpeg/.bmp/.tif
// file of the directory, sorted by name, is a view from the one stationary pose.
// An image with no layout tag in it is skipped with a warning naming it (fatal
// only when no image has tags); a layout tag never seen gets a warning too.
//
// Verdict (JudgeFloorCalibration; thresholds from FloorReportThresholds,
// read from the `floor_report:` mapping of a config file): PASS when
//   the expected BEV error 2 m ahead (BevError::rms_mm, the 1-sigma radial
//   error from the mount covariance) <= max_bev_error_2m_mm  (default 5 mm),
//   every tag's corner RMS <= max_tag_rms_px (default 1 px), over the images
//     that are not broken (more than half of their tags off by more than it),
//   every image is not broken, and its corner RMS over the tags that pass is
//     <= max_image_rms_px (default 0.5 px): one bad tag fails itself, not
//     every image it is in,
//   each image quadrant holds >= min_corners_per_quadrant tag corners over
//   all images (default 4, one tag), unless require_all_quadrants is false.
// Each failure comes with advice: which image to drop or retake, which tag to
// re-survey, which region of the image needs tags.
//
// The report (floor_report.json / .html) optionally folds in the intrinsics
// report of `calibrate intrinsics` (IntrinsicsReportSummary): one commissioning
// report with both verdicts and the overall one.
#ifndef GROUNDLINE_CALIBRATION_FLOOR_CALIBRATION_H_
#define GROUNDLINE_CALIBRATION_FLOOR_CALIBRATION_H_

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "groundline/calibration/bev_uncertainty.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/floor_extrinsics.h"
#include "groundline/calibration/floor_rectification.h"
#include "groundline/calibration/tag_detection.h"
#include "groundline/calibration/tag_layout.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct FloorReportThresholds {
  double max_bev_error_2m_mm = 5.0;
  double max_image_rms_px = 0.5;
  double max_tag_rms_px = 1.0;
  bool require_all_quadrants = true;
  int min_corners_per_quadrant = 4;

  core::Status Validate() const;
};

// Reads the optional `floor_report:` mapping of a YAML config (the keys of
// FloorReportThresholds); absent keys keep their defaults, unknown keys and
// bad values are errors naming the file, the line and the key.
core::Result<FloorReportThresholds> ReadFloorReportThresholds(const std::filesystem::path& path);

struct FloorCalibrationOptions {
  TagDetectorOptions detector;
  FloorExtrinsicsOptions solver;  // survey_sigma_m 0: the layout's survey_sigma_m
  FloorReportThresholds thresholds;
  bool rectify = true;  // build FloorCalibration::rectified for the report
  FloorRectificationOptions rectification;
  BevUncertaintyGridOptions bev_grid;  // FloorCalibration::bev_map

  core::Status Validate() const;
};

// Residuals of one layout tag over all images that saw it.
struct TagResidual {
  int id = 0;
  int images = 0;
  double rms_px = 0.0;
};

// The floor position error at one BEV point from both calibrations: the
// mount's covariance (BevError) and the intrinsics' projection uncertainty
// (the intrinsics report's Var(q) maps, projection_uncertainty.h) carried to
// the floor through the floor projection's Jacobian at that pixel,
//   Sigma_intrinsics = J_floor_pixel Var(q) J_floor_pixel',
// the two independent (they come from different data), so they add.
// rms = 1000 sqrt(trace Sigma) mm, the expected error.
struct BevErrorBudget {
  double distance_m = 0.0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // where the point is seen
  double range_m = 0.0;                             // camera to the point
  double extrinsics_rms_mm = 0.0;
  double intrinsics_rms_mm = 0.0;
  double total_rms_mm = 0.0;
  double total_sigma3_mm = 0.0;  // 3 sqrt(largest eigenvalue) of the sum
  bool known = false;            // false: the point is off the image or its Var(q) is unknown
};

struct FloorCalibration {
  FloorExtrinsicsResult solution;
  std::vector<FloorImage> images;  // the images used (with tags), solver order
  std::array<BevError, 3> bev;     // at 1, 2 and 4 m ahead on the centre line
  // bev with the intrinsics' part added (AddIntrinsicsToBev); empty without
  // an intrinsics report.
  std::vector<BevErrorBudget> bev_budget;
  // The calibration's floor uncertainty over a grid of the BEV
  // (bev_uncertainty.h): the mount's part, and the intrinsics' part once
  // AddIntrinsicsToBev has run; empty (no cells) when the camera sees none.
  BevUncertaintyMap bev_map;
  BevUncertaintyGridOptions bev_map_grid;  // the grid it was computed on
  std::vector<TagResidual> tags;   // every tag seen, worst RMS first
  // Per image, the corner RMS over the tags that pass their check (the value
  // max_image_rms_px judges; solution.image_rms_px counts every corner).
  std::vector<double> image_rms_checked_px;
  std::vector<bool> image_failed;  // per image: failed its check (advice: drop it)
  // Tag corners per image quadrant: top-left, top-right, bottom-left, bottom-right.
  std::array<int, 4> quadrant_corners{};
  // The tag field rectified with the solved mount (floor_rectification.h):
  // the layout's tag bounding box plus a margin, from the images that pass
  // their check; empty when not rectified.
  FloorRaster rectified;
  std::vector<std::string> warnings;
  FloorReportThresholds thresholds;
  bool pass = false;
  std::string verdict;                // "PASS" or "FAIL: <failures>"
  std::vector<std::string> failures;  // one line per failed check
  std::vector<std::string> advice;    // what to do next, one line each
};

// Reads the images, detects, solves, rectifies and judges. Errors: a missing
// or unreadable listed image, an image of the wrong size, no image with a
// layout tag, a failed solve.
core::Result<FloorCalibration> CalibrateFloor(const CameraModel& camera, const TagLayout& layout,
                                              const std::filesystem::path& image_dir,
                                              const FloorCalibrationOptions& options);

// Fills tags, quadrant_corners, image_rms_checked_px, image_failed,
// thresholds, pass, verdict, failures and advice
// of a calibration whose solution, images and bev are set.
void JudgeFloorCalibration(const CameraModel& camera, const FloorReportThresholds& thresholds,
                           FloorCalibration* calibration);

// The figures of an intrinsics report.json (`calibrate intrinsics`) that the
// commissioning report shows next to the floor result.
struct IntrinsicsReportSummary {
  std::string source;  // the report.json path as given
  bool pass = false;
  std::vector<std::string> failures;
  std::vector<std::string> advice;
  std::string target;
  std::string lens_model;
  double rms_px = 0.0;
  double worst_px = 0.0;
  int views = 0;
  std::array<int, 4> quadrant_corners{};
  std::array<int, 2> imager_size_px{};
  std::vector<double> intrinsics;
  std::string camera_fingerprint;  // CameraFingerprint; empty in older reports
  // Worst projection uncertainty (1 sigma) at 1, 2 and 4 m: {range_m, px, mm};
  // empty when the report has none.
  std::vector<std::array<double, 3>> projection_uncertainty;
  // Var(q) over the imager at each range (calibration_report.h), row-major
  // cells from the top-left; NaN cells where it is not known.
  struct CovarianceMap {
    double range_m = 0.0;
    int cells_x = 0, cells_y = 0;
    std::vector<Eigen::Matrix2d> covariance_px2;
  };
  std::vector<CovarianceMap> covariance_maps;  // ascending range
};
// Errors name the file and the missing or malformed field.
core::Result<IntrinsicsReportSummary> ReadIntrinsicsReportSummary(
    const std::filesystem::path& report_json);

// Whether the intrinsics report belongs to `camera` (the --camera of the floor
// calibration): same imager size, same lens model, and the same model
// (CameraFingerprint; for a report without one, the same intrinsics to 1e-9
// relative). The error names both files and what differs, and says what to do.
core::Status CheckSameCamera(const IntrinsicsReportSummary& report, const CameraModel& camera,
                             const std::string& camera_source);

// Fills calibration->bev_budget at the distances of calibration->bev (and
// calibration->bev_map over its grid, with the intrinsics' part): the
// BEV point's pixel and range through the solved mount, its Var(q) from the
// report's map cell at that pixel (linear in range between the maps' ranges,
// the nearest map outside them), carried to the floor. camera: the one the
// floor calibration used (CheckSameCamera passed).
void AddIntrinsicsToBev(const CameraModel& camera, const IntrinsicsReportSummary& intrinsics,
                        FloorCalibration* calibration);

// floor_report.json: verdict, failures with advice, mount values in mm and
// degrees with 3-sigma bounds, BEV error at 1/2/4 m, per-image and per-tag
// corner RMS, quadrant coverage, thresholds, warnings; with `intrinsics`
// (nullable) also its summary and "overall_verdict".
std::string FloorReportJson(const FloorCalibration& calibration,
                            const FloorCalibrationOptions& options,
                            const IntrinsicsReportSummary* intrinsics = nullptr);
// floor_report.html: the same figures; the rectified tag field (an embedded
// PNG) with the surveyed tag outlines drawn over it; and an SVG of the
// detected corners back-projected to the floor, their offsets enlarged.
std::string FloorReportHtml(const FloorCalibration& calibration, const TagLayout& layout,
                            const CameraModel& camera, const FloorCalibrationOptions& options,
                            const IntrinsicsReportSummary* intrinsics = nullptr);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_FLOOR_CALIBRATION_H_
