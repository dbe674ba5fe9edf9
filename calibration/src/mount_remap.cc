#include "groundline/calibration/mount_remap.h"

#include <ceres/jet.h>

namespace groundline::calibration {

bool FloorPointMountJacobian(const Eigen::Vector2d& p, const CameraMount& mount,
                             Eigen::Matrix<double, 2, 4>* J) {
  // The component order of mount_self_calibration.h: pitch, roll, height, yaw.
  using Jet = ceres::Jet<double, 4>;
  const Jet pitch(mount.pitch_rad, 0), roll(mount.roll_rad, 1), height(mount.height_m, 2),
      yaw(mount.yaw_rad, 3);
  Eigen::Matrix<Jet, 2, 1> p_b;
  if (!RemapFloorPoint<Jet>(p, mount, height, pitch, roll, yaw, mount, &p_b)) return false;
  J->row(0) = p_b(0).v.transpose();
  J->row(1) = p_b(1).v.transpose();
  return true;
}

}  // namespace groundline::calibration
