#include "groundline/calibration/floor_projection.h"

#include <cassert>
#include <sstream>
#include <utility>

namespace groundline::calibration {

FloorProjection::FloorProjection(CameraModel camera, const CameraMount& mount)
    : FloorProjection(std::move(camera), BaseFromCamera(mount)) {}

FloorProjection::FloorProjection(CameraModel camera, const Eigen::Isometry3d& T_base_cam)
    : camera_(std::move(camera)), T_base_cam_(T_base_cam), T_cam_base_(T_base_cam.inverse()) {
  assert(T_base_cam.translation().z() > 0.0);
  assert(
      (T_base_cam.linear().transpose() * T_base_cam.linear() - Eigen::Matrix3d::Identity()).norm() <
      1e-9);
}

core::Result<Eigen::Vector2d> FloorProjection::PixelOfFloorPoint(
    const Eigen::Vector2d& floor_point_m, Eigen::Matrix2d* J_pixel_floor) const {
  const Eigen::Vector3d p_cam =
      T_cam_base_ * Eigen::Vector3d(floor_point_m.x(), floor_point_m.y(), 0.0);
  if (!(p_cam.z() > 0.0)) {
    std::ostringstream out;
    out << "floor point (" << floor_point_m.x() << ", " << floor_point_m.y()
        << ") m is not in front of the camera (depth " << p_cam.z() << " m)";
    return core::Status::Error(out.str());
  }
  Eigen::Matrix<double, 2, 3> J_pixel_point;
  core::Result<Eigen::Vector2d> pixel =
      camera_.Project(p_cam, J_pixel_floor != nullptr ? &J_pixel_point : nullptr);
  if (!pixel.ok()) return pixel.status();
  if (J_pixel_floor != nullptr) {
    *J_pixel_floor = J_pixel_point * T_cam_base_.linear().leftCols<2>();
  }
  return pixel;
}

core::Result<Eigen::Vector2d> FloorProjection::FloorPointOfPixel(
    const Eigen::Vector2d& pixel, Eigen::Matrix2d* J_floor_pixel) const {
  Eigen::Matrix<double, 3, 2> J_ray_pixel;
  core::Result<Eigen::Vector3d> ray = camera_.Unproject(
      pixel, RayNormalization::kZEqualsOne, J_floor_pixel != nullptr ? &J_ray_pixel : nullptr);
  if (!ray.ok()) return ray.status();
  const Eigen::Vector3d d = T_base_cam_.linear() * *ray;
  const Eigen::Vector3d c = T_base_cam_.translation();
  if (!(d.z() < 0.0)) {
    std::ostringstream out;
    out << "pixel (" << pixel.x() << ", " << pixel.y()
        << ") is on or above the horizon: its ray does not meet the floor in front of the camera";
    return core::Status::Error(out.str());
  }
  const double s = -c.z() / d.z();
  const Eigen::Vector2d floor_point_m = c.head<2>() + s * d.head<2>();
  if (J_floor_pixel != nullptr) {
    Eigen::Matrix<double, 2, 3> J_floor_dir;
    J_floor_dir << 1.0, 0.0, -d.x() / d.z(),  //
        0.0, 1.0, -d.y() / d.z();
    *J_floor_pixel = s * J_floor_dir * T_base_cam_.linear() * J_ray_pixel;
  }
  return floor_point_m;
}

}  // namespace groundline::calibration
