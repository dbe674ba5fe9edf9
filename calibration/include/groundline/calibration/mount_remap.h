// What a change of the camera mount does to the bird's-eye view: the floor
// point that a pixel sees under one mount, moved to where the same pixel sees
// the floor under another. It needs no intrinsics: the pixel fixes a ray in
// the camera frame, and the mounts differ only in where that ray meets the
// floor.
//
// A floor point p_a = (x, y, 0) in base_link, measured with mount A (the BEV
// was made with A), lies on the camera ray
//
//   r_cam = R_base_cam(A)^T (p_a - c_A),   c = (forward_m, lateral_m, height_m),
//
// and under mount B that ray meets the floor at
//
//   d = R_base_cam(B) r_cam,   p_b = c_B + s d,   s = -c_B.z / d.z   (d.z < 0).
//
// Every straight line in the BEV stays straight (the map is the homography
// between the two floor planes), so a line measured under A becomes the line
// through its remapped points under B. The self-calibration
// (mount_self_calibration.h) evaluates this map with Ceres' Jets for the
// derivatives with respect to B.
//
// Rotation convention: camera_extrinsics.h (R_base_cam = Rz(yaw) Ry(pitch)
// Rx(roll) R_base_level). Header-only templates; pure and thread-safe.
#ifndef GROUNDLINE_CALIBRATION_MOUNT_REMAP_H_
#define GROUNDLINE_CALIBRATION_MOUNT_REMAP_H_

#include <Eigen/Core>
#include <cmath>

#include "groundline/calibration/camera_extrinsics.h"

namespace groundline::calibration {

// R_base_cam of the angles (camera_extrinsics.h), for double or a Ceres Jet.
template <typename T>
Eigen::Matrix<T, 3, 3> BaseFromCameraRotation(const T& pitch_rad, const T& roll_rad,
                                              const T& yaw_rad) {
  using std::cos;
  using std::sin;
  const T cy = cos(yaw_rad), sy = sin(yaw_rad);
  const T cp = cos(pitch_rad), sp = sin(pitch_rad);
  const T cr = cos(roll_rad), sr = sin(roll_rad);
  const T zero(0), one(1);
  Eigen::Matrix<T, 3, 3> Rz, Ry, Rx;
  Rz << cy, -sy, zero, sy, cy, zero, zero, zero, one;
  Ry << cp, zero, sp, zero, one, zero, -sp, zero, cp;
  Rx << one, zero, zero, zero, cr, -sr, zero, sr, cr;
  return Rz * Ry * Rx * LevelCameraRotation().cast<T>();
}

// The floor point p_b under mount B of the floor point p_a measured under
// mount A, both mounts' height, pitch, roll and yaw given as scalars (double
// or Ceres Jets; forward_m and lateral_m from `from_offsets` and
// `to_offsets`). Returns false, leaving p_b alone, when the ray does not go
// down under B (d.z >= -1e-9 |d|): the point would be at or beyond B's
// horizon.
template <typename T>
bool RemapFloorPointBetween(const Eigen::Matrix<T, 2, 1>& p_a, const CameraMount& from_offsets,
                            const T& from_height_m, const T& from_pitch_rad,
                            const T& from_roll_rad, const T& from_yaw_rad,
                            const T& height_m, const T& pitch_rad, const T& roll_rad,
                            const T& yaw_rad, const CameraMount& to_offsets,
                            Eigen::Matrix<T, 2, 1>* p_b) {
  const Eigen::Matrix<T, 3, 3> R_a =
      BaseFromCameraRotation(from_pitch_rad, from_roll_rad, from_yaw_rad);
  const Eigen::Matrix<T, 3, 1> r_cam =
      R_a.transpose() * Eigen::Matrix<T, 3, 1>(p_a.x() - T(from_offsets.forward_m),
                                               p_a.y() - T(from_offsets.lateral_m),
                                               -from_height_m);
  const Eigen::Matrix<T, 3, 1> d = BaseFromCameraRotation(pitch_rad, roll_rad, yaw_rad) * r_cam;
  if (!(d.z() < T(-1e-9) * r_cam.norm())) return false;
  const T s = height_m / -d.z();
  (*p_b)(0) = T(to_offsets.forward_m) + s * d.x();
  (*p_b)(1) = T(to_offsets.lateral_m) + s * d.y();
  return true;
}

// The same from a whole mount `from` (doubles) to mount B given as scalars.
template <typename T>
bool RemapFloorPoint(const Eigen::Vector2d& p_a, const CameraMount& from, const T& height_m,
                     const T& pitch_rad, const T& roll_rad, const T& yaw_rad,
                     const CameraMount& to_offsets, Eigen::Matrix<T, 2, 1>* p_b) {
  return RemapFloorPointBetween<T>(p_a.cast<T>(), from, T(from.height_m), T(from.pitch_rad),
                                   T(from.roll_rad), T(from.yaw_rad), height_m, pitch_rad,
                                   roll_rad, yaw_rad, to_offsets, p_b);
}

// The same to `reference` changed by a correction (added to its pitch, roll,
// height and yaw; Jets in the solvers that estimate the correction).
template <typename T>
bool RemapFloorPointCorrected(const Eigen::Vector2d& p_a, const CameraMount& from,
                              const CameraMount& reference, const T& d_pitch_rad,
                              const T& d_roll_rad, const T& d_height_m, const T& d_yaw_rad,
                              Eigen::Matrix<T, 2, 1>* p_b) {
  return RemapFloorPoint<T>(p_a, from, T(reference.height_m) + d_height_m,
                            T(reference.pitch_rad) + d_pitch_rad,
                            T(reference.roll_rad) + d_roll_rad, T(reference.yaw_rad) + d_yaw_rad,
                            reference, p_b);
}

// The same for two whole mounts, in doubles.
inline bool RemapFloorPoint(const Eigen::Vector2d& p_a, const CameraMount& from,
                            const CameraMount& to, Eigen::Vector2d* p_b) {
  return RemapFloorPoint<double>(p_a, from, to.height_m, to.pitch_rad, to.roll_rad, to.yaw_rad,
                                 to, p_b);
}

// d p_b / d (pitch_rad, roll_rad, height_m, yaw_rad) of B at B = `mount` for
// a floor point p measured under `mount` itself (p_b = p there): how the
// point moves when the true mount differs from the one the BEV was made with.
// It carries the mount's uncertainty into a line's or junction's covariance
// (J C_mount J^T). Returns false, leaving J alone, for a point whose ray
// does not go down (RemapFloorPoint; not a point seen on the floor).
bool FloorPointMountJacobian(const Eigen::Vector2d& p, const CameraMount& mount,
                             Eigen::Matrix<double, 2, 4>* J);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_MOUNT_REMAP_H_
