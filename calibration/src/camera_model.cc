#include "groundline/calibration/camera_model.h"

#include <cassert>
#include <cmath>
#include <sstream>
#include <utility>

#include "camera_model_internal.h"
#include "mrcal_adapter.h"

namespace groundline::calibration {
namespace {

using camera_model_internal::PointAccepted;
using camera_model_internal::ProjectOne;
using camera_model_internal::RowJacobian;

LensFamily FamilyOf(mrcal_lensmodel_type_t type) {
  switch (type) {
    case MRCAL_LENSMODEL_PINHOLE:
      return LensFamily::kPinhole;
    case MRCAL_LENSMODEL_OPENCV4:
      return LensFamily::kOpenCv4;
    case MRCAL_LENSMODEL_OPENCV5:
      return LensFamily::kOpenCv5;
    case MRCAL_LENSMODEL_OPENCV8:
      return LensFamily::kOpenCv8;
    case MRCAL_LENSMODEL_OPENCV12:
      return LensFamily::kOpenCv12;
    case MRCAL_LENSMODEL_SPLINED_STEREOGRAPHIC:
      return LensFamily::kSplinedStereographic;
    default:
      return LensFamily::kOther;
  }
}

std::string SupportedNames() {
  std::string names;
  for (const char* const* name = mrcal_supported_lensmodel_names(); *name != nullptr; ++name) {
    if (mrcal_lensmodel_type_from_name(*name) == MRCAL_LENSMODEL_CAHVORE) continue;
    names += names.empty() ? "" : ", ";
    names += *name;
  }
  return names;
}

}  // namespace

core::Result<CameraModel> CameraModel::Create(std::string_view lens_model,
                                              std::vector<double> intrinsics, int width_px,
                                              int height_px) {
  const std::string name(lens_model);
  auto impl = std::make_shared<Impl>();
  if (!mrcal_lensmodel_from_name(&impl->lensmodel, name.c_str())) {
    if (mrcal_lensmodel_type_from_name(name.c_str()) >= 0) {
      return core::Status::Error(
          "lens model '" + name +
          "' lacks its configuration values (e.g. "
          "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=16_Ny=12_fov_x_deg=100)");
    }
    return core::Status::Error("unknown lens model '" + name + "'; mrcal knows " +
                               SupportedNames());
  }
  if (impl->lensmodel.type == MRCAL_LENSMODEL_CAHVORE) {
    return core::Status::Error("lens model '" + name +
                               "' is not supported: mrcal 2.2 cannot unproject CAHVORE");
  }
  const int expected = mrcal_lensmodel_num_params(&impl->lensmodel);
  if (static_cast<int>(intrinsics.size()) != expected) {
    return core::Status::Error("lens model '" + name + "' takes " + std::to_string(expected) +
                               " intrinsics, got " + std::to_string(intrinsics.size()));
  }
  for (size_t i = 0; i < intrinsics.size(); ++i) {
    if (!std::isfinite(intrinsics[i])) {
      return core::Status::Error("intrinsics[" + std::to_string(i) + "] is not finite");
    }
  }
  const mrcal_lensmodel_metadata_t meta = mrcal_lensmodel_metadata(&impl->lensmodel);
  if (meta.has_core && !(intrinsics[0] > 0.0 && intrinsics[1] > 0.0)) {
    std::ostringstream out;
    out << "focal lengths must be > 0 px, got fx = " << intrinsics[0] << ", fy = " << intrinsics[1];
    return core::Status::Error(out.str());
  }
  if (width_px <= 0 || height_px <= 0) {
    return core::Status::Error("image size must be positive, got " + std::to_string(width_px) +
                               " x " + std::to_string(height_px) + " px");
  }
  char configured[256];
  if (!mrcal_lensmodel_name(configured, sizeof(configured), &impl->lensmodel)) {
    return core::Status::Error("lens model '" + name + "': mrcal cannot name it");
  }
  impl->name = configured;
  impl->family = FamilyOf(impl->lensmodel.type);
  impl->can_project_behind_camera = meta.can_project_behind_camera;
  impl->intrinsics = std::move(intrinsics);
  impl->width_px = width_px;
  impl->height_px = height_px;
  return CameraModel(std::move(impl));
}

CameraModel CameraModel::Pinhole(double fx, double fy, double cx, double cy, int width_px,
                                 int height_px) {
  core::Result<CameraModel> model =
      Create("LENSMODEL_PINHOLE", {fx, fy, cx, cy}, width_px, height_px);
  assert(model.ok());
  return std::move(model).value();
}

const std::string& CameraModel::lens_model() const { return impl_->name; }
LensFamily CameraModel::family() const { return impl_->family; }
const std::vector<double>& CameraModel::intrinsics() const { return impl_->intrinsics; }
int CameraModel::width_px() const { return impl_->width_px; }
int CameraModel::height_px() const { return impl_->height_px; }

Eigen::Matrix3d CameraModel::K() const {
  const std::vector<double>& p = impl_->intrinsics;
  Eigen::Matrix3d K;
  K << p[0], 0.0, p[2], 0.0, p[1], p[3], 0.0, 0.0, 1.0;
  return K;
}

core::Result<Eigen::Vector2d> CameraModel::Project(
    const Eigen::Vector3d& p_cam, Eigen::Matrix<double, 2, 3>* J_pixel_point) const {
  if (!PointAccepted(*impl_, p_cam)) {
    std::ostringstream out;
    out << "point (" << p_cam.x() << ", " << p_cam.y() << ", " << p_cam.z()
        << ") is not in front of the camera or not finite; " << impl_->name << " cannot project it";
    return core::Status::Error(out.str());
  }
  Eigen::Vector2d pixel;
  RowJacobian J;
  if (!ProjectOne(*impl_, p_cam, &pixel, J_pixel_point != nullptr ? &J : nullptr)) {
    return core::Status::Error("mrcal_project gave no finite pixel for this point");
  }
  if (J_pixel_point != nullptr) *J_pixel_point = J;
  return pixel;
}

int CameraModel::ProjectBatch(const Eigen::Ref<const Eigen::Matrix3Xd>& points_cam,
                              Eigen::Matrix2Xd* pixels, std::vector<std::uint8_t>* valid,
                              Eigen::Matrix<double, 6, Eigen::Dynamic>* J_pixel_point) const {
  assert(pixels != nullptr && valid != nullptr);
  const Eigen::Index n = points_cam.cols();
  // mrcal needs contiguous xyz triplets; a strided view is copied first.
  Eigen::Matrix3Xd contiguous;
  const double* xyz = points_cam.data();
  if (points_cam.outerStride() != 3) {
    contiguous = points_cam;
    xyz = contiguous.data();
  }
  pixels->resize(2, n);
  if (J_pixel_point != nullptr) J_pixel_point->resize(6, n);
  valid->assign(static_cast<size_t>(n), 0);
  if (n == 0) return 0;
  bool ok = true;
  if (J_pixel_point == nullptr) {
    ok = mrcal_project(mrcal_adapter::AsPoint2(pixels->data()), nullptr, nullptr,
                       mrcal_adapter::AsPoint3(xyz), static_cast<int>(n), &impl_->lensmodel,
                       impl_->intrinsics.data());
  } else {
    // libmrcal 2.2 writes every point's dq_dp into the first slot when N > 1
    // (see mrcal_adapter.h), so gradients are computed one point at a time.
    for (Eigen::Index i = 0; ok && i < n; ++i) {
      ok = mrcal_project(mrcal_adapter::AsPoint2(pixels->col(i).data()),
                         mrcal_adapter::AsPoint3(J_pixel_point->col(i).data()), nullptr,
                         mrcal_adapter::AsPoint3(xyz + 3 * i), 1, &impl_->lensmodel,
                         impl_->intrinsics.data());
    }
  }
  if (!ok) return 0;
  int count = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool good = PointAccepted(*impl_, points_cam.col(i)) && pixels->col(i).allFinite() &&
                      (J_pixel_point == nullptr || J_pixel_point->col(i).allFinite());
    (*valid)[static_cast<size_t>(i)] = good ? 1 : 0;
    count += good ? 1 : 0;
  }
  return count;
}

bool CameraModel::InImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.x() <= impl_->width_px - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() <= impl_->height_px - 0.5;
}

bool CameraModel::IsVisible(const Eigen::Vector3d& p_cam) const {
  if (!(p_cam.allFinite() && p_cam.z() > 0.0)) return false;
  core::Result<Eigen::Vector2d> pixel = Project(p_cam);
  return pixel.ok() && InImage(*pixel);
}

}  // namespace groundline::calibration
