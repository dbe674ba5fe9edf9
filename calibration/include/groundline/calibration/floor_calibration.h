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
// Verdict: PASS when the expected BEV error 2 m ahead (BevError::rms_mm, the
// 1-sigma radial error from the mount covariance) is <= max_bev_error_2m_mm
// and every used image's corner RMS is <= max_image_rms_px.
#ifndef GROUNDLINE_CALIBRATION_FLOOR_CALIBRATION_H_
#define GROUNDLINE_CALIBRATION_FLOOR_CALIBRATION_H_

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/floor_extrinsics.h"
#include "groundline/calibration/tag_detection.h"
#include "groundline/calibration/tag_layout.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct FloorCalibrationOptions {
  TagDetectorOptions detector;
  FloorExtrinsicsOptions solver;
  double max_bev_error_2m_mm = 5.0;
  double max_image_rms_px = 0.5;

  core::Status Validate() const;
};

struct FloorCalibration {
  FloorExtrinsicsResult solution;
  std::vector<FloorImage> images;  // the images used (with tags), solver order
  std::array<BevError, 3> bev;     // at 1, 2 and 4 m ahead on the centre line
  std::vector<std::string> warnings;
  bool pass = false;
  std::string verdict;  // "PASS" or "FAIL: <reasons>"
};

core::Result<FloorCalibration> CalibrateFloor(const CameraModel& camera, const TagLayout& layout,
                                              const std::filesystem::path& image_dir,
                                              const FloorCalibrationOptions& options);

// floor_report.json: mount values in mm and degrees with 3-sigma bounds, the
// BEV error at 1/2/4 m, per-image corner RMS, thresholds, verdict, warnings.
std::string FloorReportJson(const FloorCalibration& calibration,
                            const FloorCalibrationOptions& options);
// floor_report.html: the same figures and an inline SVG of the floor: the
// surveyed tag outlines and the detected corners back-projected to the floor
// through the solved mount and each image's vehicle pose.
std::string FloorReportHtml(const FloorCalibration& calibration, const TagLayout& layout,
                            const CameraModel& camera, const FloorCalibrationOptions& options);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_FLOOR_CALIBRATION_H_
