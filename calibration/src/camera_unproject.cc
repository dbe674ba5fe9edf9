// CameraModel's unprojection: mrcal_unproject, then Newton polishing in the
// tangent plane of the ray (see camera_model.h).
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cassert>
#include <cmath>
#include <sstream>

#include "camera_model_internal.h"
#include "groundline/calibration/camera_model.h"
#include "mrcal_adapter.h"

namespace groundline::calibration {
namespace {

using camera_model_internal::ProjectOne;
using camera_model_internal::RowJacobian;

// Newton polishing of mrcal_unproject's ray (see the header).
constexpr int kMaxNewtonSteps = 6;
constexpr double kConvergedPx = 1e-11;
constexpr double kAcceptedPx = 1e-6;

// Orthonormal basis (3x2) of the plane orthogonal to the unit vector u.
Eigen::Matrix<double, 3, 2> TangentBasis(const Eigen::Vector3d& u) {
  Eigen::Matrix<double, 3, 2> T;
  T.col(0) = u.unitOrthogonal();
  T.col(1) = u.cross(T.col(0));
  return T;
}

// Polishes the unit ray *u until it projects onto q; on success *J is the
// projection Jacobian at the final *u.
bool RefineRay(const CameraModel::Impl& impl, const Eigen::Vector2d& q, Eigen::Vector3d* u,
               RowJacobian* J) {
  Eigen::Vector2d q_hat;
  for (int step = 0;; ++step) {
    if (!ProjectOne(impl, *u, &q_hat, J)) return false;
    const Eigen::Vector2d residual = q - q_hat;
    if (residual.norm() <= kConvergedPx) return true;
    if (step == kMaxNewtonSteps) return residual.norm() <= kAcceptedPx;
    const Eigen::Matrix<double, 3, 2> T = TangentBasis(*u);
    const Eigen::Matrix2d A = *J * T;
    if (!(std::abs(A.determinant()) > 0.0)) return false;
    *u = (*u + T * A.inverse() * residual).normalized();
    if (!u->allFinite()) return false;
  }
}

// The ray for `normalization`, from the refined unit ray u with projection
// Jacobian J at u; J_ray_pixel as documented in the header.
bool FinishRay(const Eigen::Vector3d& u, const RowJacobian& J, RayNormalization normalization,
               Eigen::Vector3d* ray, Eigen::Matrix<double, 3, 2>* J_ray_pixel) {
  if (normalization == RayNormalization::kUnitNorm) {
    *ray = u;
    if (J_ray_pixel != nullptr) {
      const Eigen::Matrix<double, 3, 2> T = TangentBasis(u);
      *J_ray_pixel = T * (J * T).inverse();
    }
    return true;
  }
  if (!(u.z() > 0.0)) return false;
  *ray = u / u.z();
  if (J_ray_pixel != nullptr) {
    // The projection Jacobian at ray = u / u_z is J * u_z (degree -1 in scale).
    const Eigen::Matrix2d A = J.leftCols<2>() * u.z();
    J_ray_pixel->topRows<2>() = A.inverse();
    J_ray_pixel->row(2).setZero();
  }
  return true;
}

std::string PixelText(const Eigen::Vector2d& q) {
  std::ostringstream out;
  out << "pixel (" << q.x() << ", " << q.y() << ")";
  return out.str();
}

}  // namespace

core::Result<Eigen::Vector3d> CameraModel::Unproject(
    const Eigen::Vector2d& pixel, RayNormalization normalization,
    Eigen::Matrix<double, 3, 2>* J_ray_pixel) const {
  Eigen::Vector3d v;
  if (!pixel.allFinite() ||
      !mrcal_unproject(mrcal_adapter::AsPoint3(v.data()), mrcal_adapter::AsPoint2(pixel.data()), 1,
                       &impl_->lensmodel, impl_->intrinsics.data()) ||
      !v.allFinite() || v.squaredNorm() == 0.0) {
    return core::Status::Error(PixelText(pixel) + ": mrcal_unproject found no ray");
  }
  Eigen::Vector3d u = v.normalized();
  RowJacobian J;
  if (!RefineRay(*impl_, pixel, &u, &J)) {
    return core::Status::Error(PixelText(pixel) + ": the unprojected ray does not reproject onto " +
                               "the pixel within 1e-6 px");
  }
  Eigen::Vector3d ray;
  if (!FinishRay(u, J, normalization, &ray, J_ray_pixel)) {
    return core::Status::Error(PixelText(pixel) + ": its ray does not point forward (z <= 0)");
  }
  return ray;
}

int CameraModel::UnprojectBatch(const Eigen::Ref<const Eigen::Matrix2Xd>& pixels,
                                RayNormalization normalization, Eigen::Matrix3Xd* rays,
                                std::vector<std::uint8_t>* valid) const {
  assert(rays != nullptr && valid != nullptr);
  const Eigen::Index n = pixels.cols();
  Eigen::Matrix2Xd contiguous;
  const double* xy = pixels.data();
  if (pixels.outerStride() != 2) {
    contiguous = pixels;
    xy = contiguous.data();
  }
  rays->resize(3, n);
  valid->assign(static_cast<size_t>(n), 0);
  if (n == 0) return 0;
  // mrcal reports failure for the batch as a whole; bad rays are caught per
  // point below.
  mrcal_unproject(mrcal_adapter::AsPoint3(rays->data()), mrcal_adapter::AsPoint2(xy),
                  static_cast<int>(n), &impl_->lensmodel, impl_->intrinsics.data());
  int count = 0;
  RowJacobian J;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d q(xy[2 * i], xy[2 * i + 1]);
    Eigen::Vector3d u = rays->col(i);
    bool good = q.allFinite() && u.allFinite() && u.squaredNorm() > 0.0;
    if (good) {
      u.normalize();
      Eigen::Vector3d ray;
      good = RefineRay(*impl_, q, &u, &J) && FinishRay(u, J, normalization, &ray, nullptr);
      if (good) rays->col(i) = ray;
    }
    (*valid)[static_cast<size_t>(i)] = good ? 1 : 0;
    count += good ? 1 : 0;
  }
  return count;
}

}  // namespace groundline::calibration
