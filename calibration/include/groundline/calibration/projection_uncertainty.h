// Projection uncertainty of an intrinsic calibration: how far the pixel of a
// point at a given range may move because the calibration's intrinsics are
// uncertain, mrcal's method (http://mrcal.secretsauce.net/uncertainty.html;
// mrcal 2.2 model_analysis.py projection_uncertainty, finite range, which
// mrcal-show-projection-uncertainty plots).
//
// The camera is the calibration's reference frame. A point p_cam is carried
// into every board frame i with the solved pose (p_i = T_i^-1 p_cam), brought
// back through the perturbed poses and averaged ("mean-frames": the camera
// frame itself is only defined by where the boards were), then projected
// through the perturbed intrinsics:
//   q(b) = project(mean_i T_i(b) p_i, intrinsics(b))
//   Var(q) = dq/db Var(b) dq/db'       (Var(b): CalibrationCovariance)
// The board flex does not enter q; its uncertainty does through Var(b)'s
// coupling. mrcal evaluates the same expression in its packed state; the
// result does not depend on the state's scaling.
//
// Figures, for a 2x2 Var(q):
//   worst_px   sqrt(largest eigenvalue): the 1-sigma error in the worst
//              direction (mrcal's "worstdirection-stdev");
//   worst_mm   the same mapped to the plane through the point perpendicular
//              to its viewing ray, through the projection's local 2x2
//              Jacobian on that plane: the 1-sigma lateral position error on
//              a surface seen face on at that range. A floor seen obliquely
//              stretches the along-range part by 1/sin(grazing angle); the
//              floor report does that with the real mount.
// Pure functions; thread-safe.
#ifndef GROUNDLINE_CALIBRATION_PROJECTION_UNCERTAINTY_H_
#define GROUNDLINE_CALIBRATION_PROJECTION_UNCERTAINTY_H_

#include <Eigen/Core>
#include <vector>

#include "groundline/calibration/intrinsic_calibration.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct ProjectionUncertainty {
  Eigen::Matrix2d covariance_px2 = Eigen::Matrix2d::Zero();
  double worst_px = 0.0;
  double worst_mm = 0.0;
};

// For a point in the camera frame (m). Fails when the calibration has no
// covariance, or the point does not project.
core::Result<ProjectionUncertainty> ProjectionUncertaintyOfPoint(
    const IntrinsicCalibration& calibration, const Eigen::Vector3d& p_cam);

// For the point range_m along the viewing ray of pixel q (as mrcal's tool:
// unproject, normalize, scale by the range).
core::Result<ProjectionUncertainty> ProjectionUncertaintyOfPixel(
    const IntrinsicCalibration& calibration, const Eigen::Vector2d& q, double range_m);

// The figures at the centres of a cells_x x cells_y grid over the imager,
// row-major from the top-left; NaN where a figure cannot be computed.
struct UncertaintyMap {
  double range_m = 0.0;
  int cells_x = 0;
  int cells_y = 0;
  std::vector<double> worst_px;
  std::vector<double> worst_mm;
  std::vector<Eigen::Matrix2d> covariance_px2;  // NaN where not computable
  // Centre of cell (ix, iy), px.
  Eigen::Vector2d CellCentre(int ix, int iy, int width_px, int height_px) const;
};
// cells_x, cells_y >= 1, range_m > 0 (asserted).
UncertaintyMap ComputeUncertaintyMap(const IntrinsicCalibration& calibration, double range_m,
                                     int cells_x, int cells_y);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_PROJECTION_UNCERTAINTY_H_
