// FloorProjection: the floor "homography" of a real, distorted camera. Floor
// points (x, y, 0) in base_link map to pixels through the mount T_base_cam
// (camera_extrinsics.h, docs/extrinsics.md) and the lens model
// (camera_model.h); pixels map back by unprojecting and intersecting the
// viewing ray with the floor plane z = 0. For LENSMODEL_PINHOLE both agree
// with the plane-induced homography FloorToImageHomography(T_base_cam, K).
//
// Forward, floor -> pixel:
//   p_cam = R_cam_base (x, y, 0)^T + t_cam_base,   pixel = project(p_cam),
//   J_pixel_floor = J_project(p_cam) * [R_cam_base e_x, R_cam_base e_y]    (2x2, px/m).
// Backward, pixel -> floor: the ray r (camera frame, z = 1) of the pixel,
// turned into base_link, d = R_base_cam r, from the optical centre c = t_base_cam:
//   s = -c_z / d_z (> 0 only when d_z < 0: the ray goes down),
//   (x, y) = c_xy + s d_xy,
//   J_floor_pixel = s ([I2 0] - d_xy e_z^T / d_z) R_base_cam J_ray_pixel   (2x2, m/px),
// the Jacobian that carries pixel noise to floor-point covariance,
// Sigma_floor = J Sigma_px J^T.
//
// Units: metres on the floor, pixels in the image (camera_model.h pixel
// convention). Immutable after construction; all methods are const and
// thread-safe.
#ifndef GROUNDLINE_CALIBRATION_FLOOR_PROJECTION_H_
#define GROUNDLINE_CALIBRATION_FLOOR_PROJECTION_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

class FloorProjection {
 public:
  // The mount must be valid (asserted).
  FloorProjection(CameraModel camera, const CameraMount& mount);
  // T_base_cam must be a rigid transform with the camera above the floor,
  // translation z > 0 (asserted).
  FloorProjection(CameraModel camera, const Eigen::Isometry3d& T_base_cam);

  const CameraModel& camera() const { return camera_; }
  const Eigen::Isometry3d& T_base_cam() const { return T_base_cam_; }

  // The pixel of the floor point (x, y) in base_link, metres. Fails when the
  // point is not in front of the camera (depth z_cam <= 0) or does not
  // project. The pixel may lie outside the image (camera().InImage tells).
  core::Result<Eigen::Vector2d> PixelOfFloorPoint(const Eigen::Vector2d& floor_point_m,
                                                  Eigen::Matrix2d* J_pixel_floor = nullptr) const;

  // The floor point (x, y) in base_link seen at a pixel. Fails for pixels on
  // or above the horizon (their ray does not go down, d_z >= 0), and for
  // pixels that do not unproject to a forward ray.
  core::Result<Eigen::Vector2d> FloorPointOfPixel(const Eigen::Vector2d& pixel,
                                                  Eigen::Matrix2d* J_floor_pixel = nullptr) const;

 private:
  CameraModel camera_;
  Eigen::Isometry3d T_base_cam_;
  Eigen::Isometry3d T_cam_base_;
};

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_FLOOR_PROJECTION_H_
