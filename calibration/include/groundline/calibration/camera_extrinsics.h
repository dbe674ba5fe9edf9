// Camera extrinsics: where the camera sits on the vehicle, and the floor
// homography of inverse perspective mapping (IPM) that follows from it.
//
// Frames (docs/extrinsics.md, ROS REP-103):
// - base_link: x forward, y left, z up, origin on the floor at the midpoint of
//   the drive axle. The floor is the plane z = 0.
// - camera: the optical frame, z forward along the optical axis, x right (image
//   columns grow), y down (image rows grow).
//
// A CameraMount describes T_base_cam with six numbers. Rotation order:
//
//   R_base_cam = Rz(yaw) * Ry(pitch) * Rx(roll) * R_base_level
//
// where R_base_level is the level camera (pitch = roll = yaw = 0: optical axis
// along base +x, image right along base -y, image down along base -z):
//
//   R_base_level = [0 0 1; -1 0 0; 0 -1 0]   (columns: camera x, y, z in base).
//
// Rz, Ry, Rx are right-handed rotations about the base axes. Read intrinsically
// (z-y'-x''): first turn the level camera by yaw about the vertical (positive =
// to the left), then tilt it by pitch about its new left axis (positive = the
// optical axis goes down toward the floor), then roll it by roll about the
// resulting optical axis (positive = the image's right edge goes down).
// The camera's optical centre is at (forward_m, lateral_m, height_m) in base_link.
//
// Functions are pure and thread-safe.
#ifndef GROUNDLINE_CALIBRATION_CAMERA_EXTRINSICS_H_
#define GROUNDLINE_CALIBRATION_CAMERA_EXTRINSICS_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>

#include "groundline/core/status.h"

namespace groundline::calibration {

// The defaults are the reference vehicle of docs/extrinsics.md (0.58 m high,
// pitched 42.4 deg down, 0.42 m ahead of the axle); commissioning replaces them.
struct CameraMount {
  double height_m = 0.58;                            // optical centre above the floor, > 0
  double pitch_rad = 42.4 * std::numbers::pi / 180;  // tilt down, |pitch| < pi/2
  double roll_rad = 0.0;                             // about the optical axis, in [-pi, pi]
  double yaw_rad = 0.0;     // about the vertical, positive to the left, in [-pi, pi]
  double forward_m = 0.42;  // optical centre ahead of base_link along base x
  double lateral_m = 0.0;   // optical centre along base y, left positive

  // Ok when every value is finite, height_m > 0, |pitch_rad| < pi/2 and roll and
  // yaw lie in [-pi, pi]; otherwise the message names the first bad field.
  core::Status Validate() const;
};

// Whether two mounts are the same (every component within tolerance rad or
// m; the default absorbs a round trip through degrees in a text file).
bool SameMount(const CameraMount& a, const CameraMount& b, double tolerance = 1e-9);

// The rotation R_base_level of the level camera (see the file comment).
Eigen::Matrix3d LevelCameraRotation();

// T_base_cam: maps points from the camera optical frame into base_link,
// p_base = T_base_cam * p_cam. The mount must be valid (asserted).
Eigen::Isometry3d BaseFromCamera(const CameraMount& mount);

// The mount whose BaseFromCamera(mount) is T_base_cam (angles of the z-y'-x''
// decomposition, roll and yaw in (-pi, pi]). Fails, with a message, when the
// rotation is not orthonormal (tolerance 1e-9), when the camera is not above
// the floor (height <= 0), or when |pitch| is within 1e-9 rad of pi/2 (the
// gimbal-lock case where roll and yaw are not separable).
core::Result<CameraMount> MountFromBaseCamera(const Eigen::Isometry3d& T_base_cam);

// The floor homography of IPM (the plane-induced homography of the floor):
//
//   H_img_floor = K [r1 r2 t],   [r1 r2 r3] = R_cam_base,  t = t_cam_base,
//
// so that lambda (u, v, 1)^T = H_img_floor (x, y, 1)^T for a floor point
// (x, y, 0) in base_link and its pixel (u, v) in an ideal pinhole camera with
// intrinsic matrix K = [fx s cx; 0 fy cy; 0 0 1] (pixels; K(2, 2) must be 1).
// H is deliberately not rescaled: lambda equals the depth z_cam of the floor
// point in the camera frame, so its sign tells front from behind.
// Requires T_base_cam with the camera above the floor (then det H != 0).
Eigen::Matrix3d FloorToImageHomography(const Eigen::Isometry3d& T_base_cam,
                                       const Eigen::Matrix3d& K);

// The mount of a floor homography (the inverse of FloorToImageHomography with
// K = I): H_norm_floor maps floor points (x, y, 1) of base_link to normalized
// image points (x/z, y/z, 1) of the camera, up to scale and sign. The scale is
// fixed by the mean length of its first two columns (r1, r2 of R_cam_base), the
// sign by a positive depth at `floor_point_in_view` (a floor point the camera
// sees), the rotation [r1 r2 r1 x r2] is projected onto SO(3) (SVD), and the
// third column is t_cam_base. A homography estimated from noisy points is thus
// turned into the nearest rigid mount; an exact one is reproduced. Fails when
// the matrix is not finite or singular, when its columns are not near a
// rotation's (column lengths differ by more than a factor 1.5: not a
// floor-to-normalized-image homography, e.g. one still in pixels), or as
// MountFromBaseCamera fails.
core::Result<CameraMount> MountFromFloorHomography(const Eigen::Matrix3d& H_norm_floor,
                                                   const Eigen::Vector2d& floor_point_in_view);

// H_floor_img = H_img_floor^-1, the back-projection of IPM. H_img_floor must come
// from FloorToImageHomography (asserted invertible).
Eigen::Matrix3d ImageToFloorHomography(const Eigen::Matrix3d& H_img_floor);

// Pixel (u, v) of the floor point (x, y) in base_link. Fails when the point is
// not in front of the camera (depth z_cam <= 0).
core::Result<Eigen::Vector2d> ProjectFloorPoint(const Eigen::Matrix3d& H_img_floor,
                                                const Eigen::Vector2d& floor_point_m);

// The floor point (x, y) in base_link seen at pixel (u, v). Fails for pixels on
// or above the horizon, whose ray never meets the floor in front of the camera.
// J_floor_pixel (2x2, m/px), if given, is d(x, y)/d(u, v): the Jacobian that
// carries pixel noise to floor-point covariance, Sigma_floor = J Sigma_px J^T.
core::Result<Eigen::Vector2d> BackProjectPixel(const Eigen::Matrix3d& H_floor_img,
                                               const Eigen::Vector2d& pixel,
                                               Eigen::Matrix2d* J_floor_pixel = nullptr);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_CAMERA_EXTRINSICS_H_
