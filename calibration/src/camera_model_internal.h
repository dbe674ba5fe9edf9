// Internals shared by camera_model.cc and camera_unproject.cc.
#ifndef GROUNDLINE_CALIBRATION_SRC_CAMERA_MODEL_INTERNAL_H_
#define GROUNDLINE_CALIBRATION_SRC_CAMERA_MODEL_INTERNAL_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "groundline/calibration/camera_model.h"
#include "mrcal_adapter.h"

namespace groundline::calibration {

struct CameraModel::Impl {
  mrcal_lensmodel_t lensmodel;
  std::string name;
  LensFamily family;
  bool can_project_behind_camera;
  std::vector<double> intrinsics;
  int width_px;
  int height_px;
};

namespace camera_model_internal {

using RowJacobian = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;

// Whether Project accepts p: finite, and in front of the camera unless the
// model can project points behind it.
inline bool PointAccepted(const CameraModel::Impl& impl, const Eigen::Vector3d& p) {
  if (!p.allFinite()) return false;
  return impl.can_project_behind_camera ? p.squaredNorm() > 0.0 : p.z() > 0.0;
}

// Projects one point; false when mrcal fails or the pixel is not finite.
inline bool ProjectOne(const CameraModel::Impl& impl, const Eigen::Vector3d& p, Eigen::Vector2d* q,
                       RowJacobian* J) {
  const bool ok =
      mrcal_project(mrcal_adapter::AsPoint2(q->data()),
                    J != nullptr ? mrcal_adapter::AsPoint3(J->data()) : nullptr, nullptr,
                    mrcal_adapter::AsPoint3(p.data()), 1, &impl.lensmodel, impl.intrinsics.data());
  return ok && q->allFinite() && (J == nullptr || J->allFinite());
}

}  // namespace camera_model_internal
}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_SRC_CAMERA_MODEL_INTERNAL_H_
