#include "groundline/calibration/projection_uncertainty.h"

#include <Eigen/Eigenvalues>
#include <cassert>
#include <cmath>
#include <limits>

#include "mrcal_adapter.h"

namespace groundline::calibration {

core::Result<ProjectionUncertainty> ProjectionUncertaintyOfPoint(
    const IntrinsicCalibration& calibration, const Eigen::Vector3d& p_cam) {
  if (!calibration.covariance) {
    return core::Status::Error("no calibration covariance: " + calibration.covariance_error);
  }
  const CalibrationCovariance& cov = *calibration.covariance;
  const CameraModel& camera = calibration.camera;
  mrcal_lensmodel_t lensmodel{};
  if (!mrcal_lensmodel_from_name(&lensmodel, camera.lens_model().c_str())) {
    return core::Status::Error("mrcal does not know lens model " + camera.lens_model());
  }
  const std::vector<double>& intrinsics = camera.intrinsics();
  const int n_intrinsics = static_cast<int>(intrinsics.size());
  const int n_state = static_cast<int>(cov.covariance.rows());
  const int n_views = static_cast<int>(calibration.views.size());

  // One point per mrcal_project call: libmrcal 2.2's batched gradients are
  // wrong beyond the first point (mrcal_adapter.h).
  mrcal_point2_t q;
  mrcal_point3_t dq_dp[2];
  std::vector<double> dq_dintrinsics(2 * n_intrinsics);
  if (!(p_cam.z() > 0.0) ||
      !mrcal_project(&q, dq_dp, dq_dintrinsics.data(), mrcal_adapter::AsPoint3(p_cam.data()), 1,
                     &lensmodel, intrinsics.data()) ||
      !std::isfinite(q.x) || !std::isfinite(q.y)) {
    return core::Status::Error("the point does not project");
  }
  Eigen::Matrix<double, 2, 3> J_q_p;
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) J_q_p(r, c) = dq_dp[r].xyz[c];

  Eigen::MatrixXd J_q_b = Eigen::MatrixXd::Zero(2, n_state);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < n_intrinsics; ++c)
      J_q_b(r, cov.state_index_intrinsics + c) = dq_dintrinsics[r * n_intrinsics + c];
  // Mean-frames: d(mean_i T_i p_i)/d rt_i = (1/N) d(T_i p_i)/d rt_i.
  for (int i = 0; i < n_views; ++i) {
    const double* rt = calibration.views[i].rt_cam_board.data();
    double p_board[3];
    mrcal_transform_point_rt_inverted(p_board, nullptr, nullptr, rt, p_cam.data());
    double p_back[3];
    double J_rt[18];  // 3x6 row-major
    mrcal_transform_point_rt(p_back, J_rt, nullptr, rt, p_board);
    const Eigen::Map<const Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J_p_rt(J_rt);
    J_q_b.block<2, 6>(0, cov.state_index_frames + 6 * i) = J_q_p * J_p_rt / n_views;
  }
  ProjectionUncertainty out;
  out.covariance_px2 = J_q_b * cov.covariance * J_q_b.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig_q(out.covariance_px2);
  out.worst_px = std::sqrt(std::max(0.0, eig_q.eigenvalues()(1)));

  // Lateral error on the plane perpendicular to the ray: q moves by J_q_p E
  // for a move E d (d in m) of the point on that plane.
  const Eigen::Vector3d ray = p_cam.normalized();
  Eigen::Vector3d e1 = ray.cross(Eigen::Vector3d::UnitY());
  if (e1.norm() < 1e-6) e1 = ray.cross(Eigen::Vector3d::UnitX());
  e1.normalize();
  const Eigen::Vector3d e2 = ray.cross(e1).normalized();
  Eigen::Matrix<double, 3, 2> E;
  E << e1, e2;
  const Eigen::Matrix2d A = J_q_p * E;  // px per m
  if (std::abs(A.determinant()) < 1e-12) return core::Status::Error("degenerate projection");
  const Eigen::Matrix2d A_inv = A.inverse();
  const Eigen::Matrix2d cov_m2 = A_inv * out.covariance_px2 * A_inv.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig_m(cov_m2);
  out.worst_mm = 1e3 * std::sqrt(std::max(0.0, eig_m.eigenvalues()(1)));
  return out;
}

core::Result<ProjectionUncertainty> ProjectionUncertaintyOfPixel(
    const IntrinsicCalibration& calibration, const Eigen::Vector2d& q, double range_m) {
  core::Result<Eigen::Vector3d> ray = calibration.camera.Unproject(q, RayNormalization::kUnitNorm);
  if (!ray.ok()) return ray.status();
  return ProjectionUncertaintyOfPoint(calibration, range_m * ray->normalized());
}

Eigen::Vector2d UncertaintyMap::CellCentre(int ix, int iy, int width_px, int height_px) const {
  return {(ix + 0.5) * width_px / cells_x - 0.5, (iy + 0.5) * height_px / cells_y - 0.5};
}

UncertaintyMap ComputeUncertaintyMap(const IntrinsicCalibration& calibration, double range_m,
                                     int cells_x, int cells_y) {
  assert(cells_x >= 1 && cells_y >= 1 && range_m > 0.0);
  UncertaintyMap map;
  map.range_m = range_m;
  map.cells_x = cells_x;
  map.cells_y = cells_y;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  map.worst_px.assign(static_cast<std::size_t>(cells_x) * cells_y, nan);
  map.worst_mm.assign(map.worst_px.size(), nan);
  map.covariance_px2.assign(map.worst_px.size(), Eigen::Matrix2d::Constant(nan));
  const int w = calibration.camera.width_px();
  const int h = calibration.camera.height_px();
  for (int iy = 0; iy < cells_y; ++iy) {
    for (int ix = 0; ix < cells_x; ++ix) {
      const core::Result<ProjectionUncertainty> u =
          ProjectionUncertaintyOfPixel(calibration, map.CellCentre(ix, iy, w, h), range_m);
      if (!u.ok()) continue;
      map.worst_px[iy * cells_x + ix] = u->worst_px;
      map.worst_mm[iy * cells_x + ix] = u->worst_mm;
      map.covariance_px2[iy * cells_x + ix] = u->covariance_px2;
    }
  }
  return map;
}

}  // namespace groundline::calibration
