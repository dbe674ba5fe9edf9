#include "groundline/calibration/mount_remap.h"

#include <ceres/jet.h>

namespace groundline::calibration {

bool FloorPointMountJacobian(const Eigen::Vector2d& p, const CameraMount& mount,
                             Eigen::Matrix<double, 2, 4>* J) {
  // The component order of mount_self_calibration.h: pitch, roll, height, yaw.
  using Jet = ceres::Jet<double, 4>;
  Eigen::Matrix<Jet, 2, 1> p_b;
  if (!RemapFloorPointCorrected<Jet>(p, mount, mount, Jet(0.0, 0), Jet(0.0, 1), Jet(0.0, 2),
                                     Jet(0.0, 3), &p_b))
    return false;
  J->row(0) = p_b(0).v.transpose();
  J->row(1) = p_b(1).v.transpose();
  return true;
}

}  // namespace groundline::calibration
