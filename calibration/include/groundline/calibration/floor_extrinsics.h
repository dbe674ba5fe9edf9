// Floor extrinsics: the camera mount (camera_extrinsics.h) from AprilTags lying
// on the floor at surveyed positions (tag_layout.h), seen in one or more images.
//
// Model. A tag corner c (layout frame, on the floor z = 0) seen in image i,
// taken with base_link at T_floor_base_i (identity for base_link layouts):
//   p_base = T_floor_base_i^-1 * c                        (planar, z = 0)
//   p_cam  = R_base_cam(theta)^T (p_base - t_base_cam(theta))
//   pixel  = project(p_cam)                               (camera_model.h)
// theta = (height_m, pitch_rad, roll_rad, yaw_rad, forward_m, lateral_m), the
// CameraMount. The ground-plane prior is built in: the corners are points of
// z = 0, so the one pose that explains all tags is found directly, and IPPE's
// per-tag two-fold ambiguity never arises.
//
// Jacobian (analytic, checked in tests). With R = Rz(yaw) Ry(pitch) Rx(roll) L,
// dR/dtheta_k = [a_k]x R for a_yaw = e_z, a_pitch = Rz e_y, a_roll = Rz Ry e_x,
// so with q = p_base - t:
//   d p_cam / d theta_angle_k = -R^T (a_k x q),
//   d p_cam / d (forward, lateral, height) = -R^T (e_x, e_y, e_z),
//   J_pixel_mount = J_pixel_point * d p_cam / d theta.
//
// Solve. Initialization: one DLT homography between all corners in base_link
// and their unprojected rays (z = 1), pooled over the images, decomposed into
// R_cam_base, t_cam_base; the same from each single image (>= 8 corners)
// competes, and the start with the smallest median corner residual over all
// images wins (an image with a wrong vehicle pose spoils only the pooled one). Refinement: Ceres
// Levenberg-Marquardt over the six numbers with a Huber loss (huber_px) on each corner's 2-D pixel
// residual, over the corners whose residual at the start is within the outlier gate,
// max(outlier_gate_px, 5 x the median residual): gross outliers (an image
// taken at another pose than surveyed) would drag the mount until their
// points come into view, the Huber loss cannot stop that.
// Covariance: ceres::Covariance of the six numbers, scaled by sigma^2 where
// sigma is corner_sigma_px when it is given (> 0) and otherwise
//   sigma = max(sqrt(sum |r|^2 / (2 N - 6)), min_corner_sigma_px),
// the a posteriori residual standard deviation with a floor: on rendered and
// real images libapriltag's corners carry a bias that the residuals do not
// show (straight-line edge fits on lens-curved edges), and the a posteriori
// scale alone put the truth inside 3 sigma in only 0-15 % of the simulated
// trials; with the 0.3 px floor, 100 % (benchmarks/calibration/floor_extrinsics_trials).
// Survey error: when survey_sigma_m > 0 each surveyed corner is taken to be
// off by an isotropic N(0, survey_sigma_m^2 I2) error, the same in every image
// that sees it, and the covariance gains
//   A^-1 (sum_c B_c B_c^T) A^-1 survey_sigma_m^2,  B_c = sum_i J_i^T G_ic,
// with A = sum J_i^T J_i (the unscaled information), J_i the 2x6 pixel Jacobian
// of corner c in image i and G_ic = d pixel / d corner floor position (2x2).
//
// Observability: with the vehicle poses known in the floor frame (or the tags
// given in base_link), every corner is a known point in base_link, and all
// six numbers are observable from one image with >= 2 tags not on one line
// through the camera; several images at different poses condition it better.
#ifndef GROUNDLINE_CALIBRATION_FLOOR_EXTRINSICS_H_
#define GROUNDLINE_CALIBRATION_FLOOR_EXTRINSICS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using MountJacobian = Eigen::Matrix<double, 2, 6>;

// One tag corner in one image.
struct FloorCorner {
  int tag_id = 0;
  int corner = 0;                                     // 0..3, det->p order
  Eigen::Vector2d floor_m = Eigen::Vector2d::Zero();  // in the layout's frame
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();    // detected
};

struct FloorImage {
  std::string name;
  core::SE2 T_floor_base;  // identity when the layout is in base_link
  std::vector<FloorCorner> corners;
};

struct FloorExtrinsicsOptions {
  double huber_px = 1.0;             // Huber loss scale on the corner residual norm
  double corner_sigma_px = 0.0;      // > 0: stated corner noise; 0: a posteriori
  double min_corner_sigma_px = 0.3;  // floor on the a posteriori corner noise (px)
  double survey_sigma_m = 0.0;       // 1-sigma error of each surveyed corner (m, per axis)
  double outlier_gate_px = 20.0;     // corners off the initial mount by more are left out
  int max_iterations = 100;

  core::Status Validate() const;
};

struct FloorExtrinsicsResult {
  CameraMount mount;
  CameraMount initial_mount;  // from the pooled homography
  // Covariance of (height_m, pitch_rad, roll_rad, yaw_rad, forward_m, lateral_m).
  Matrix6d covariance = Matrix6d::Zero();
  double sigma_px = 0.0;               // the scale applied to the covariance (see the file comment)
  double a_posteriori_sigma_px = 0.0;  // sqrt(sum |r|^2 / (2 N - 6))
  double survey_sigma_m = 0.0;         // the survey error folded into the covariance
  double rms_px = 0.0;                 // RMS of the corner residual norm, corners in the solve
  // Per FloorImage, same order, over all its corners (0 for none; infinite
  // when a corner does not project through the solved mount).
  std::vector<double> image_rms_px;
  int corners = 0;
  int gated_corners = 0;  // left out of the solve by the outlier gate
  // Solver summary.
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  std::string termination;
  double solve_time_s = 0.0;
};

// The point in the camera frame of the floor point p_floor_m (layout frame) seen
// from T_floor_base; J_cam_mount (3x6) is d p_cam / d theta.
Eigen::Vector3d FloorPointInCamera(const CameraMount& mount, const core::SE2& T_floor_base,
                                   const Eigen::Vector2d& p_floor_m,
                                   Eigen::Matrix<double, 3, 6>* J_cam_mount = nullptr);

// The pixel of a floor point; fails when it does not project.
core::Result<Eigen::Vector2d> PredictFloorPixel(const CameraModel& camera, const CameraMount& mount,
                                                const core::SE2& T_floor_base,
                                                const Eigen::Vector2d& p_floor_m,
                                                MountJacobian* J_pixel_mount = nullptr);

// Fails when no image has corners, when fewer than 8 corners are given, when
// the initialization is degenerate, or when the solver does not converge.
core::Result<FloorExtrinsicsResult> SolveFloorExtrinsics(const CameraModel& camera,
                                                         const std::vector<FloorImage>& images,
                                                         const FloorExtrinsicsOptions& options);

// The error of IPM at the floor point distance_m ahead of base_link on the
// centre line caused by the mount's uncertainty: the pixel that sees the point
// is back-projected through a perturbed mount. Independent of the intrinsics
// (they cancel): J_floor_mount = -(J_n_floor)^-1 J_n_mount on the normalized
// image plane. cov_floor_m2 = J Sigma J^T (2x2, base x and y).
struct BevError {
  double distance_m = 0.0;
  Eigen::Matrix2d cov_floor_m2 = Eigen::Matrix2d::Zero();
  double rms_mm = 0.0;     // sqrt(trace cov), the expected error
  double sigma3_mm = 0.0;  // 3 sqrt(largest eigenvalue): the 3-sigma bound
};
core::Result<BevError> BevErrorAhead(const CameraMount& mount, const Matrix6d& covariance,
                                     double distance_m);
// The same at any floor point (x, y) of base_link (distance_m: its x).
core::Result<BevError> BevErrorAt(const CameraMount& mount, const Matrix6d& covariance,
                                  const Eigen::Vector2d& floor_point_m);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_FLOOR_EXTRINSICS_H_
