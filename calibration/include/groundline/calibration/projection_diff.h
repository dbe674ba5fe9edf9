// The projection difference of two intrinsic calibrations of one camera, the
// way mrcal computes it (http://mrcal.secretsauce.net/differencing.html;
// mrcal 2.2 model_analysis.py projection_diff, the tool
// mrcal-show-projection-diff): how far apart the two models put the pixel of
// the same point, after the camera frames the two calibrations imply are
// lined up.
//
// The imager is gridded (grid_width x grid_height points from pixel (0, 0) to
// (W-1, H-1), mrcal's sample_imager); each grid pixel q0 is unprojected
// through both models (unit rays v0, v1). Two calibrations of one lens do not
// share their camera frame exactly (each is defined by where its boards
// were), so a transformation T10 from frame 0 to frame 1 is fitted on the
// grid points within focus_radius_px of the imager centre, minimising
//   sum rho(th2(T10 p0, v1)^2),  th2(a, b) = 2 (1 - a.b / |a|)  (~ angle^2)
// with rho the Huber loss at (5 deg)^2, as mrcal does; p0 = v0 at infinity
// (T10 a rotation), p0 = distance_m v0 otherwise (T10 a rotation and a
// translation). Then q1 = project_1(T10 p0) and the difference is q1 - q0.
// With intrinsics_only, T10 is the identity (the lenses compared in isolation).
//
// mrcal can also weight the fit by both models' projection uncertainties,
// which needs the calibration's optimization inputs; this implementation fits
// on the focus circle only (mrcal's use_uncertainties=False, whose default
// radius, min(W, H) / 6, is the default here too).
//
// Pure functions; thread-safe.
#ifndef GROUNDLINE_CALIBRATION_PROJECTION_DIFF_H_
#define GROUNDLINE_CALIBRATION_PROJECTION_DIFF_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct ProjectionDiffOptions {
  int grid_width = 60;      // points across the imager (mrcal's gridn_width)
  int grid_height = 0;      // 0: round(H / W * grid_width), a square-ish grid
  double distance_m = 0.0;  // 0: points at infinity (a rotation-only fit)
  bool intrinsics_only = false;
  double focus_radius_px = -1.0;  // < 0: min(W, H) / 6, around the imager centre
  // Checks the values above; the error names the field.
  core::Status Validate() const;
};

struct ProjectionDiff {
  int grid_width = 0, grid_height = 0;
  double focus_radius_px = 0.0;  // as used
  // Row-major from the top-left grid point: the pixel q0, the vector
  // q1 - q0 and its length (NaN where a model cannot unproject or project).
  std::vector<Eigen::Vector2d> q0;
  std::vector<Eigen::Vector2d> difference_px;
  std::vector<double> length_px;
  // T10: p1 = R10 p0 + t10 (t10 = 0 at infinity), and what the fit used.
  Eigen::Matrix3d R10 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t10 = Eigen::Vector3d::Zero();
  int fit_points = 0;
  // Summary figures over the grid points within the focus circle and over
  // the whole grid (finite points only).
  double focus_median_px = 0.0, focus_max_px = 0.0;
  double imager_median_px = 0.0, imager_max_px = 0.0;
};

// Fails when the options are invalid, the imager sizes differ, fewer than 3
// grid points of the focus circle unproject in both models, or the fit fails.
core::Result<ProjectionDiff> ComputeProjectionDiff(const CameraModel& model0,
                                                   const CameraModel& model1,
                                                   const ProjectionDiffOptions& options = {});

// The difference as a picture a technician reads at a glance: the imager
// (width_px x height_px, the models' size) coloured by |q1 - q0| on the
// viridis scale from 0 to max_px (beyond it saturated), grey where a model
// cannot map the pixel, the focus circle in white, and under it a scale bar
// labelled in px. BGR, 8 bit. Asserts max_px > 0.
cv::Mat RenderProjectionDiff(const ProjectionDiff& diff, int width_px, int height_px,
                             double max_px);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_PROJECTION_DIFF_H_
