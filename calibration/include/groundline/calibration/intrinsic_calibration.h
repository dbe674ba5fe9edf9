// Intrinsic calibration of one camera from views of a planar board, solved by
// libmrcal's mrcal_optimize (mrcal 2.2 C API).
//
// Problem. The camera is the reference frame (no extrinsics); every view i
// contributes a board pose rt_cam_board[i] (mrcal's frames_toref: p_cam =
// R(r) p_board + t, r Rodrigues in rad, t in m) and the pixel observations of
// its corners. Unknowns: the intrinsics of `lens_model`, every board pose
// and, with optimize_board_warp, mrcal's board flex (calobject_warp: the board
// is a paraboloid z = x2 * 4 xr (1 - xr) + y2 * 4 yr (1 - yr), xr, yr in [0, 1]
// across the grid, x2 y2 in m). Residual of a corner: r = q_projected -
// q_observed (px). mrcal's regularization (on by default) and outlier
// rejection (on by default: mrcal drops observations beyond a few standard
// deviations and re-solves) are mrcal's own.
//
// Seed. OpenCV's cv::calibrateCamera on the same corners (Zhang's method then
// Levenberg-Marquardt) with 5 distortion terms (fewer for PINHOLE/OPENCV4);
// its result is also reported (`opencv_seed`), and with
// seed_fix_aspect_ratio = true it is the fx = fy solve of OpenCV's
// calibration sample (CALIB_FIX_ASPECT_RATIO), which mrcal cannot impose.
// The mrcal solve starts from it, the extra OPENCV8/12 terms at 0, in two
// stages: intrinsics and poses first (no board flex, no outlier rejection),
// then the full problem.
//
// Error conventions (px), over the inliers of the final solve:
//   rms_px       = sqrt(mean over corners of |r|^2)  (per point, 2D vectors;
//                  OpenCV's calibrateCamera return value and its sample's
//                  avg_reprojection_error use the same convention)
//   worst_px     = max |r|
//   per view: the same over that view's corners.
// Supported lens models: LENSMODEL_PINHOLE, OPENCV4, OPENCV5, OPENCV8,
// OPENCV12 (others need a seed OpenCV cannot give).
#ifndef GROUNDLINE_CALIBRATION_INTRINSIC_CALIBRATION_H_
#define GROUNDLINE_CALIBRATION_INTRINSIC_CALIBRATION_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "groundline/calibration/board_detection.h"
#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct IntrinsicCalibrationOptions {
  std::string lens_model = "LENSMODEL_OPENCV8";
  bool optimize_board_warp = true;  // as mrcal-calibrate-cameras
  bool regularization = true;
  bool outlier_rejection = true;
  bool seed_fix_aspect_ratio = false;  // OpenCV seed with fx = fy
  int min_views = 3;
  bool verbose = false;  // mrcal's solver trace on stderr
  core::Status Validate() const;
};

struct CalibrationView {
  std::string name;  // image file name, for reports
  BoardObservation observation;
};

struct ViewResult {
  std::string name;
  std::array<double, 6> rt_cam_board{};      // rx ry rz (rad) tx ty tz (m)
  std::vector<int> grid_index;               // as observed
  std::vector<Eigen::Vector2d> observed_px;  // as observed
  std::vector<Eigen::Vector2d> residual_px;  // projected - observed
  std::vector<std::uint8_t> outlier;         // 1: rejected by mrcal
  double rms_px = 0.0;                       // inliers, per point
  double worst_px = 0.0;                     // inliers
  int inliers = 0;
};

// OpenCV's calibrateCamera on the same corners (the seed).
struct OpenCvSeedResult {
  std::vector<double> intrinsics;  // fx fy cx cy k1 k2 p1 p2 k3
  double rms_px = 0.0;             // calibrateCamera's return value (per point)
  std::vector<double> per_view_rms_px;
  double mean_per_view_rms_px = 0.0;  // average of per_view_rms_px
};

struct IntrinsicCalibrationSummary {
  double rms_px = 0.0;
  double worst_px = 0.0;
  int points = 0;    // observed corners
  int outliers = 0;  // of those, rejected by mrcal
  // mrcal's own figure (mrcal_stats_t, what mrcal-calibrate-cameras prints):
  // per coordinate, about rms_px / sqrt(2), with the regularization terms.
  double mrcal_rms_px = 0.0;
  // Largest difference between groundline's residual of an inlier and
  // mrcal's measurement vector (a self-check; ~1e-9 px).
  double residual_check_px = 0.0;
  std::optional<std::array<double, 2>> board_warp_m;  // x2 y2
  double solve_time_s = 0.0;
};

// The covariance of the solved state, as mrcal's uncertainty propagation
// defines it (http://mrcal.secretsauce.net/uncertainty.html; mrcal 2.2
// model_analysis.py, _propagate_calibration_uncertainty): with J the
// Jacobian of the measurement vector (board residuals, then mrcal's
// regularization terms) at the optimum and J_obs its board-residual rows,
//   Var(b) = sigma^2 inv(J'J) J_obs' J_obs inv(J'J),
// sigma = the standard deviation of the inlier residual coordinates (mrcal's
// default observed_pixel_uncertainty: np.std of residuals_chessboard).
// b is mrcal's state vector in its own units (not the solver's scaled,
// "packed" form): intrinsics (px, unitless distortion), then each view's
// board pose rt_cam_board (rad, m), then the board flex (m).
struct CalibrationCovariance {
  Eigen::MatrixXd covariance;  // Nstate x Nstate
  int state_index_intrinsics = 0;
  int state_index_frames = 0;  // view i's pose at state_index_frames + 6 i
  int state_index_warp = -1;   // -1: the board flex was not solved
  double observed_pixel_sigma_px = 0.0;
};

struct IntrinsicCalibration {
  CameraModel camera;
  std::vector<ViewResult> views;
  IntrinsicCalibrationSummary summary;
  OpenCvSeedResult opencv_seed;
  // The problem as solved, for the covariance's users and mrcal's
  // optimization_inputs (mrcal_optimization_inputs.h).
  BoardGrid grid;
  IntrinsicCalibrationOptions options;
  // Empty when J'J was singular (the views do not constrain every
  // parameter): the report then says so and fails.
  std::optional<CalibrationCovariance> covariance;
  std::string covariance_error;  // why covariance is empty
};

// Fails, saying what to do, with fewer than min_views views, a view with fewer
// than 4 corners, an unsupported lens model, or a seed/solve that does not
// produce a valid camera. Options must be valid (asserted).
core::Result<IntrinsicCalibration> CalibrateIntrinsics(const std::vector<CalibrationView>& views,
                                                       const BoardGrid& grid, int width_px,
                                                       int height_px,
                                                       const IntrinsicCalibrationOptions& options);

// mrcal's corners.vnl text for mrcal-calibrate-cameras
// (`# filename x y level`, one line per grid point in row-major order, '-'
// for a point not observed), so that mrcal's own tool can be run on exactly
// groundline's corners. Level 0 = full weight.
std::string MrcalCornersVnl(const std::vector<CalibrationView>& views, const BoardGrid& grid);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_INTRINSIC_CALIBRATION_H_
