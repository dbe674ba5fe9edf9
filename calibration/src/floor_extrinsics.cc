#include "groundline/calibration/floor_extrinsics.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace groundline::calibration {
namespace {

constexpr int kHeight = 0, kPitch = 1, kRoll = 2, kYaw = 3, kForward = 4, kLateral = 5;

std::array<double, 6> ToParams(const CameraMount& m) {
  return {m.height_m, m.pitch_rad, m.roll_rad, m.yaw_rad, m.forward_m, m.lateral_m};
}

CameraMount FromParams(const double* p) {
  CameraMount m;
  m.height_m = p[kHeight];
  m.pitch_rad = p[kPitch];
  m.roll_rad = p[kRoll];
  m.yaw_rad = p[kYaw];
  m.forward_m = p[kForward];
  m.lateral_m = p[kLateral];
  return m;
}

// The pixel residual of one corner, analytic Jacobian (file comment of the header).
class CornerCost : public ceres::SizedCostFunction<2, 6> {
 public:
  CornerCost(const CameraModel* camera, const core::SE2& T_floor_base, const FloorCorner& corner)
      : camera_(camera), T_floor_base_(T_floor_base), corner_(corner) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const CameraMount mount = FromParams(parameters[0]);
    if (!mount.Validate().ok()) return false;
    MountJacobian J;
    const core::Result<Eigen::Vector2d> pixel = PredictFloorPixel(
        *camera_, mount, T_floor_base_, corner_.floor_m, jacobians && jacobians[0] ? &J : nullptr);
    if (!pixel.ok()) return false;
    Eigen::Map<Eigen::Vector2d> r(residuals);
    r = *pixel - corner_.pixel;
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_out(jacobians[0]);
      J_out = J;
    }
    return true;
  }

 private:
  const CameraModel* camera_;
  core::SE2 T_floor_base_;
  FloorCorner corner_;
};

// The survey term of the covariance for a unit survey sigma (header comment):
// A^-1 (sum_c B_c B_c^T) A^-1 with A^-1 = unscaled_cov.
Matrix6d SurveyCovariance(const CameraModel& camera, const std::vector<FloorImage>& images,
                          const CameraMount& mount, const Matrix6d& unscaled_cov) {
  std::map<std::pair<int, int>, Eigen::Matrix<double, 6, 2>> B;
  const Eigen::Isometry3d T_base_cam = BaseFromCamera(mount);
  for (const FloorImage& im : images) {
    const Eigen::Matrix2d R_base_floor = im.T_floor_base.Inverse().Rotation();
    const Eigen::Matrix<double, 3, 2> J_cam_floor =
        T_base_cam.linear().transpose().leftCols<2>() * R_base_floor;
    for (const FloorCorner& c : im.corners) {
      MountJacobian J;
      const Eigen::Vector3d p_cam = FloorPointInCamera(mount, im.T_floor_base, c.floor_m);
      Eigen::Matrix<double, 2, 3> J_pixel_cam;
      if (!camera.Project(p_cam, &J_pixel_cam).ok()) continue;
      if (!PredictFloorPixel(camera, mount, im.T_floor_base, c.floor_m, &J).ok()) continue;
      auto [it, inserted] =
          B.try_emplace({c.tag_id, c.corner}, Eigen::Matrix<double, 6, 2>::Zero());
      it->second += J.transpose() * (J_pixel_cam * J_cam_floor);
    }
  }
  Matrix6d sum = Matrix6d::Zero();
  for (const auto& [key, b] : B) sum += b * b.transpose();
  return unscaled_cov * sum * unscaled_cov;
}

// Hartley-normalized DLT of the homography a -> b (both 2-D, N >= 4).
Eigen::Matrix3d Homography(const std::vector<Eigen::Vector2d>& a,
                           const std::vector<Eigen::Vector2d>& b) {
  const auto normalizer = [](const std::vector<Eigen::Vector2d>& pts) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : pts) mean += p;
    mean /= static_cast<double>(pts.size());
    double dist = 0.0;
    for (const auto& p : pts) dist += (p - mean).norm();
    const double s = std::sqrt(2.0) * static_cast<double>(pts.size()) / std::max(dist, 1e-12);
    Eigen::Matrix3d T;
    T << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
    return T;
  };
  const Eigen::Matrix3d Ta = normalizer(a), Tb = normalizer(b);
  Eigen::MatrixXd A(2 * a.size(), 9);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector3d p = Ta * a[i].homogeneous();
    const Eigen::Vector3d q = Tb * b[i].homogeneous();
    const auto r = static_cast<Eigen::Index>(2 * i);
    A.row(r) << 0, 0, 0, -q.z() * p.transpose(), q.y() * p.transpose();
    A.row(r + 1) << q.z() * p.transpose(), 0, 0, 0, -q.x() * p.transpose();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d H;
  H << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  return Tb.inverse() * H * Ta;
}

// The mount from the pooled homography base floor -> normalized image plane.
core::Result<CameraMount> InitialMount(const CameraModel& camera,
                                       const std::vector<FloorImage>& images) {
  std::vector<Eigen::Vector2d> floor, image;
  for (const FloorImage& im : images) {
    const core::SE2 T_base_floor = im.T_floor_base.Inverse();
    for (const FloorCorner& c : im.corners) {
      const core::Result<Eigen::Vector3d> ray =
          camera.Unproject(c.pixel, RayNormalization::kZEqualsOne);
      if (!ray.ok()) continue;
      floor.push_back(T_base_floor * c.floor_m);
      image.push_back(ray->head<2>());
    }
  }
  if (floor.size() < 8) {
    return core::Status::Error("floor extrinsics: only " + std::to_string(floor.size()) +
                               " corners unproject; need at least 8 (two tags)");
  }
  core::Result<CameraMount> mount = MountFromFloorHomography(Homography(floor, image), floor[0]);
  if (!mount.ok()) {
    return core::Status::Error(
        "floor extrinsics: initialization from the tags' pooled homography failed (do the tags "
        "lie on one line? add tags spread across the image): " +
        mount.message());
  }
  return mount;
}

// The median corner residual norm of a mount over all images (inf when a
// corner does not project).
double MedianResidualPx(const CameraModel& camera, const std::vector<FloorImage>& images,
                        const CameraMount& mount) {
  std::vector<double> norms;
  for (const FloorImage& im : images) {
    for (const FloorCorner& c : im.corners) {
      const core::Result<Eigen::Vector2d> px =
          PredictFloorPixel(camera, mount, im.T_floor_base, c.floor_m);
      norms.push_back(px.ok() ? (*px - c.pixel).norm() : std::numeric_limits<double>::infinity());
    }
  }
  if (norms.empty()) return std::numeric_limits<double>::infinity();
  std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
  return norms[norms.size() / 2];
}

// The pooled initialization, or the one of a single image when that explains
// the corners of all images better (smaller median residual): one image with
// a wrong vehicle pose must not spoil the start of the refinement.
core::Result<CameraMount> RobustInitialMount(const CameraModel& camera,
                                             const std::vector<FloorImage>& images) {
  core::Result<CameraMount> best = InitialMount(camera, images);
  if (images.size() < 2) return best;
  double best_median =
      best.ok() ? MedianResidualPx(camera, images, *best) : std::numeric_limits<double>::infinity();
  for (const FloorImage& im : images) {
    if (im.corners.size() < 8) continue;
    const core::Result<CameraMount> one = InitialMount(camera, {im});
    if (!one.ok()) continue;
    const double median = MedianResidualPx(camera, images, *one);
    if (median < best_median) {
      best = one;
      best_median = median;
    }
  }
  return best;
}

}  // namespace

core::Status FloorExtrinsicsOptions::Validate() const {
  if (!(huber_px > 0.0))
    return core::Status::Error("FloorExtrinsicsOptions.huber_px: expected > 0");
  if (!(corner_sigma_px >= 0.0)) {
    return core::Status::Error("FloorExtrinsicsOptions.corner_sigma_px: expected >= 0");
  }
  if (!(min_corner_sigma_px >= 0.0)) {
    return core::Status::Error("FloorExtrinsicsOptions.min_corner_sigma_px: expected >= 0");
  }
  if (!(outlier_gate_px > 0.0)) {
    return core::Status::Error("FloorExtrinsicsOptions.outlier_gate_px: expected > 0");
  }
  if (!(survey_sigma_m >= 0.0)) {
    return core::Status::Error("FloorExtrinsicsOptions.survey_sigma_m: expected >= 0");
  }
  if (max_iterations < 1) {
    return core::Status::Error("FloorExtrinsicsOptions.max_iterations: expected >= 1");
  }
  return core::Status::Ok();
}

Eigen::Vector3d FloorPointInCamera(const CameraMount& mount, const core::SE2& T_floor_base,
                                   const Eigen::Vector2d& p_floor_m,
                                   Eigen::Matrix<double, 3, 6>* J_cam_mount) {
  const Eigen::Isometry3d T_base_cam = BaseFromCamera(mount);
  const Eigen::Matrix3d& R = T_base_cam.linear();
  const Eigen::Vector2d p_base = T_floor_base.Inverse() * p_floor_m;
  const Eigen::Vector3d q = Eigen::Vector3d(p_base.x(), p_base.y(), 0.0) - T_base_cam.translation();
  const Eigen::Vector3d p_cam = R.transpose() * q;
  if (J_cam_mount != nullptr) {
    const Eigen::Matrix3d Rz = Eigen::AngleAxisd(mount.yaw_rad, Eigen::Vector3d::UnitZ()).matrix();
    const Eigen::Matrix3d Ry =
        Eigen::AngleAxisd(mount.pitch_rad, Eigen::Vector3d::UnitY()).matrix();
    const Eigen::Vector3d a_yaw = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d a_pitch = Rz * Eigen::Vector3d::UnitY();
    const Eigen::Vector3d a_roll = Rz * Ry * Eigen::Vector3d::UnitX();
    J_cam_mount->col(kHeight) = -R.transpose().col(2);
    J_cam_mount->col(kPitch) = -R.transpose() * a_pitch.cross(q);
    J_cam_mount->col(kRoll) = -R.transpose() * a_roll.cross(q);
    J_cam_mount->col(kYaw) = -R.transpose() * a_yaw.cross(q);
    J_cam_mount->col(kForward) = -R.transpose().col(0);
    J_cam_mount->col(kLateral) = -R.transpose().col(1);
  }
  return p_cam;
}

core::Result<Eigen::Vector2d> PredictFloorPixel(const CameraModel& camera, const CameraMount& mount,
                                                const core::SE2& T_floor_base,
                                                const Eigen::Vector2d& p_floor_m,
                                                MountJacobian* J_pixel_mount) {
  Eigen::Matrix<double, 3, 6> J_cam_mount;
  const Eigen::Vector3d p_cam =
      FloorPointInCamera(mount, T_floor_base, p_floor_m, J_pixel_mount ? &J_cam_mount : nullptr);
  Eigen::Matrix<double, 2, 3> J_pixel_cam;
  core::Result<Eigen::Vector2d> pixel =
      camera.Project(p_cam, J_pixel_mount ? &J_pixel_cam : nullptr);
  if (!pixel.ok()) return pixel.status();
  if (J_pixel_mount != nullptr) *J_pixel_mount = J_pixel_cam * J_cam_mount;
  return pixel;
}

core::Result<FloorExtrinsicsResult> SolveFloorExtrinsics(const CameraModel& camera,
                                                         const std::vector<FloorImage>& images,
                                                         const FloorExtrinsicsOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  FloorExtrinsicsResult result;
  for (const FloorImage& im : images) result.corners += static_cast<int>(im.corners.size());
  if (result.corners < 8) {
    return core::Status::Error("floor extrinsics: " + std::to_string(result.corners) +
                               " tag corners in all images; need at least 8 (two tags)");
  }
  core::Result<CameraMount> initial = RobustInitialMount(camera, images);
  if (!initial.ok()) return initial.status();
  result.initial_mount = *initial;

  std::array<double, 6> params = ToParams(*initial);
  // Gross outliers at the start (an image with a wrong vehicle pose, a tag
  // surveyed far off) stay out of the solve: beyond the gate, or not in
  // front of the camera at all.
  const double gate_px =
      std::max(options.outlier_gate_px, 5.0 * MedianResidualPx(camera, images, *initial));
  std::vector<std::vector<bool>> used(images.size());
  int used_corners = 0;
  ceres::Problem problem;
  for (std::size_t i = 0; i < images.size(); ++i) {
    for (const FloorCorner& c : images[i].corners) {
      const core::Result<Eigen::Vector2d> px =
          PredictFloorPixel(camera, *initial, images[i].T_floor_base, c.floor_m);
      used[i].push_back(px.ok() && (*px - c.pixel).norm() <= gate_px);
      if (!used[i].back()) continue;
      ++used_corners;
      problem.AddResidualBlock(new CornerCost(&camera, images[i].T_floor_base, c),
                               new ceres::HuberLoss(options.huber_px), params.data());
    }
  }
  result.gated_corners = result.corners - used_corners;
  if (used_corners < 8) {
    return core::Status::Error(
        "floor extrinsics: the images disagree: only " + std::to_string(used_corners) +
        " corners agree with the initial mount; check the vehicle poses and the tag survey");
  }
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  const auto start = std::chrono::steady_clock::now();
  ceres::Solve(solver_options, &problem, &summary);
  result.solve_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.iterations = static_cast<int>(summary.iterations.size());
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.termination = ceres::TerminationTypeToString(summary.termination_type);
  if (summary.termination_type != ceres::CONVERGENCE) {
    return core::Status::Error("floor extrinsics: the solver did not converge (" +
                               summary.BriefReport() + ")");
  }
  result.mount = FromParams(params.data());
  if (core::Status s = result.mount.Validate(); !s.ok()) {
    return s.WithContext("floor extrinsics: the solution is not a valid mount");
  }

  double sum_sq = 0.0;  // over the corners in the solve
  for (std::size_t i = 0; i < images.size(); ++i) {
    double image_sq = 0.0;
    for (std::size_t j = 0; j < images[i].corners.size(); ++j) {
      const FloorCorner& c = images[i].corners[j];
      const core::Result<Eigen::Vector2d> px =
          PredictFloorPixel(camera, result.mount, images[i].T_floor_base, c.floor_m);
      const double sq =
          px.ok() ? (*px - c.pixel).squaredNorm() : std::numeric_limits<double>::infinity();
      image_sq += sq;
      if (used[i][j]) sum_sq += sq;
    }
    const std::size_t n = images[i].corners.size();
    result.image_rms_px.push_back(n == 0 ? 0.0 : std::sqrt(image_sq / static_cast<double>(n)));
  }
  result.rms_px = std::sqrt(sum_sq / used_corners);
  result.a_posteriori_sigma_px = std::sqrt(sum_sq / std::max(1, 2 * used_corners - 6));
  result.sigma_px = options.corner_sigma_px > 0.0
                        ? options.corner_sigma_px
                        : std::max(result.a_posteriori_sigma_px, options.min_corner_sigma_px);

  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(cov_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {
      {params.data(), params.data()}};
  if (!covariance.Compute(blocks, &problem)) {
    return core::Status::Error(
        "floor extrinsics: the mount is not observable from these tags "
        "(rank-deficient Jacobian); spread the tags over the image");
  }
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> cov;
  covariance.GetCovarianceBlock(params.data(), params.data(), cov.data());
  result.covariance = result.sigma_px * result.sigma_px * cov;
  result.survey_sigma_m = options.survey_sigma_m;
  if (options.survey_sigma_m > 0.0) {
    result.covariance += SurveyCovariance(camera, images, result.mount, cov) *
                         (options.survey_sigma_m * options.survey_sigma_m);
  }
  return result;
}

core::Result<BevError> BevErrorAhead(const CameraMount& mount, const Matrix6d& covariance,
                                     double distance_m) {
  return BevErrorAt(mount, covariance, Eigen::Vector2d(distance_m, 0.0));
}

core::Result<BevError> BevErrorAt(const CameraMount& mount, const Matrix6d& covariance,
                                  const Eigen::Vector2d& p) {
  Eigen::Matrix<double, 3, 6> J_cam_mount;
  const Eigen::Vector3d p_cam = FloorPointInCamera(mount, core::SE2::Identity(), p, &J_cam_mount);
  if (p_cam.z() <= 1e-6) {
    return core::Status::Error("BEV error: the floor point (" + std::to_string(p.x()) + ", " +
                               std::to_string(p.y()) + ") m is not in front of the camera");
  }
  // Normalized projection n = (x / z, y / z).
  Eigen::Matrix<double, 2, 3> J_n_cam;
  J_n_cam << 1 / p_cam.z(), 0, -p_cam.x() / (p_cam.z() * p_cam.z()), 0, 1 / p_cam.z(),
      -p_cam.y() / (p_cam.z() * p_cam.z());
  const Eigen::Matrix3d R_cam_base = BaseFromCamera(mount).linear().transpose();
  const Eigen::Matrix2d J_n_floor = J_n_cam * R_cam_base.leftCols<2>();
  const Eigen::Matrix<double, 2, 6> J_floor_mount = -J_n_floor.inverse() * (J_n_cam * J_cam_mount);
  BevError e;
  e.distance_m = p.x();
  e.cov_floor_m2 = J_floor_mount * covariance * J_floor_mount.transpose();
  e.rms_mm = 1000.0 * std::sqrt(e.cov_floor_m2.trace());
  const double lmax =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(e.cov_floor_m2).eigenvalues().maxCoeff();
  e.sigma3_mm = 3000.0 * std::sqrt(std::max(lmax, 0.0));
  return e;
}

}  // namespace groundline::calibration
