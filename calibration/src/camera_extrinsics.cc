#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/mount_remap.h"
#include "groundline/core/angles.h"

#include <cassert>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>

namespace groundline::calibration {
namespace {

using core::kRadToDeg;
// Tolerances of MountFromBaseCamera (see the header).
constexpr double kOrthonormalityTol = 1e-9;
constexpr double kGimbalLockCos = 1e-9;

std::string FieldError(const char* field, const std::string& expected, double value,
                       bool is_angle = false) {
  std::ostringstream out;
  out.precision(17);
  out << "camera mount field '" << field << "': expected " << expected << ", got " << value;
  if (is_angle && std::isfinite(value)) out << " (" << value * kRadToDeg << " deg)";
  return out.str();
}

// Maps -pi to pi so that angles come back in (-pi, pi].
double HalfOpenAngle(double angle_rad) {
  return angle_rad == -std::numbers::pi ? std::numbers::pi : angle_rad;
}

}  // namespace

core::Status CameraMount::Validate() const {
  struct Field {
    const char* name;
    double value;
  };
  for (const Field& f :
       {Field{"height_m", height_m}, Field{"pitch_rad", pitch_rad}, Field{"roll_rad", roll_rad},
        Field{"yaw_rad", yaw_rad}, Field{"forward_m", forward_m}, Field{"lateral_m", lateral_m}}) {
    if (!std::isfinite(f.value))
      return core::Status::Error(FieldError(f.name, "a finite number", f.value));
  }
  if (height_m <= 0.0) {
    return core::Status::Error(FieldError("height_m", "a height above the floor > 0 m", height_m));
  }
  if (std::abs(pitch_rad) >= std::numbers::pi / 2) {
    return core::Status::Error(FieldError("pitch_rad", "|pitch| < pi/2", pitch_rad, true));
  }
  if (std::abs(roll_rad) > std::numbers::pi) {
    return core::Status::Error(FieldError("roll_rad", "an angle in [-pi, pi]", roll_rad, true));
  }
  if (std::abs(yaw_rad) > std::numbers::pi) {
    return core::Status::Error(FieldError("yaw_rad", "an angle in [-pi, pi]", yaw_rad, true));
  }
  return core::Status::Ok();
}

Eigen::Matrix3d LevelCameraRotation() {
  Eigen::Matrix3d r;
  r << 0.0, 0.0, 1.0,  //
      -1.0, 0.0, 0.0,  //
      0.0, -1.0, 0.0;
  return r;
}

Eigen::Isometry3d BaseFromCamera(const CameraMount& mount) {
  assert(mount.Validate().ok());
  Eigen::Isometry3d T_base_cam = Eigen::Isometry3d::Identity();
  T_base_cam.linear() = BaseFromCameraRotation(mount.pitch_rad, mount.roll_rad, mount.yaw_rad);
  T_base_cam.translation() = Eigen::Vector3d(mount.forward_m, mount.lateral_m, mount.height_m);
  return T_base_cam;
}

core::Result<CameraMount> MountFromBaseCamera(const Eigen::Isometry3d& T_base_cam) {
  const Eigen::Matrix3d r = T_base_cam.linear();
  const Eigen::Vector3d t = T_base_cam.translation();
  if (!r.allFinite() || !t.allFinite()) {
    return core::Status::Error("T_base_cam has non-finite entries");
  }
  const double orthonormality_error = (r.transpose() * r - Eigen::Matrix3d::Identity()).norm();
  if (orthonormality_error > kOrthonormalityTol || r.determinant() <= 0.0) {
    return core::Status::Error(
        "T_base_cam: the rotation is not a proper orthonormal matrix (|R^T R - I| = " +
        std::to_string(orthonormality_error) + ", det = " + std::to_string(r.determinant()) + ")");
  }
  if (t.z() <= 0.0) {
    return core::Status::Error("T_base_cam: the camera is not above the floor (height " +
                               std::to_string(t.z()) + " m, expected > 0)");
  }
  // M = Rz(yaw) Ry(pitch) Rx(roll); its last row is (-sin p, cos p sin r, cos p cos r).
  const Eigen::Matrix3d m = r * LevelCameraRotation().transpose();
  const double cos_pitch = std::hypot(m(0, 0), m(1, 0));
  if (cos_pitch < kGimbalLockCos) {
    return core::Status::Error(
        "T_base_cam: the optical axis is vertical (pitch = +-90 deg); roll and yaw are not "
        "separable and such a mount is not valid");
  }
  CameraMount mount;
  mount.height_m = t.z();
  mount.forward_m = t.x();
  mount.lateral_m = t.y();
  mount.pitch_rad = std::atan2(-m(2, 0), cos_pitch);
  mount.yaw_rad = HalfOpenAngle(std::atan2(m(1, 0), m(0, 0)));
  mount.roll_rad = HalfOpenAngle(std::atan2(m(2, 1), m(2, 2)));
  return mount;
}

Eigen::Matrix3d FloorToImageHomography(const Eigen::Isometry3d& T_base_cam,
                                       const Eigen::Matrix3d& K) {
  assert(K(2, 0) == 0.0 && K(2, 1) == 0.0 && K(2, 2) == 1.0);
  assert(T_base_cam.translation().z() > 0.0);
  const Eigen::Isometry3d T_cam_base = T_base_cam.inverse();
  Eigen::Matrix3d plane;
  plane.col(0) = T_cam_base.linear().col(0);
  plane.col(1) = T_cam_base.linear().col(1);
  plane.col(2) = T_cam_base.translation();
  return K * plane;
}

Eigen::Matrix3d ImageToFloorHomography(const Eigen::Matrix3d& H_img_floor) {
  Eigen::Matrix3d H_floor_img;
  bool invertible = false;
  H_img_floor.computeInverseWithCheck(H_floor_img, invertible);
  assert(invertible);
  (void)invertible;
  return H_floor_img;
}

core::Result<CameraMount> MountFromFloorHomography(const Eigen::Matrix3d& H_norm_floor,
                                                   const Eigen::Vector2d& floor_point_in_view) {
  if (!H_norm_floor.allFinite() || !floor_point_in_view.allFinite()) {
    return core::Status::Error("floor homography: not finite");
  }
  const double n1 = H_norm_floor.col(0).norm(), n2 = H_norm_floor.col(1).norm();
  if (!(n1 > 0.0 && n2 > 0.0) || std::abs(H_norm_floor.determinant()) < 1e-12 * n1 * n2 * n1) {
    return core::Status::Error("floor homography: singular");
  }
  if (std::max(n1, n2) > 1.5 * std::min(n1, n2)) {
    std::ostringstream out;
    out << "floor homography: its first two columns (the floor's axes seen from the camera) "
           "differ in length by a factor "
        << std::max(n1, n2) / std::min(n1, n2)
        << ", expected about 1 for a homography from the floor to normalized image "
           "coordinates (one in pixels needs K^-1 first)";
    return core::Status::Error(out.str());
  }
  // H = s [r1 r2 t] with R = R_cam_base.
  Eigen::Matrix3d H = H_norm_floor / (0.5 * (n1 + n2));
  if ((H * floor_point_in_view.homogeneous()).z() < 0.0) H = -H;
  Eigen::Matrix3d R;
  R << H.col(0), H.col(1), H.col(0).cross(H.col(1));
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0.0) return core::Status::Error("floor homography: degenerate rotation");
  Eigen::Isometry3d T_cam_base = Eigen::Isometry3d::Identity();
  T_cam_base.linear() = R;
  T_cam_base.translation() = H.col(2);
  return MountFromBaseCamera(T_cam_base.inverse());
}

core::Result<Eigen::Vector2d> ProjectFloorPoint(const Eigen::Matrix3d& H_img_floor,
                                                const Eigen::Vector2d& floor_point_m) {
  const Eigen::Vector3d m = H_img_floor * floor_point_m.homogeneous();
  // m.z() is the depth of the floor point in the camera frame (see the header).
  if (!(m.z() > 0.0)) {
    std::ostringstream out;
    out << "floor point (" << floor_point_m.x() << ", " << floor_point_m.y()
        << ") m is not in front of the camera (depth " << m.z() << " m)";
    return core::Status::Error(out.str());
  }
  return Eigen::Vector2d(m.hnormalized());
}

core::Result<Eigen::Vector2d> BackProjectPixel(const Eigen::Matrix3d& H_floor_img,
                                               const Eigen::Vector2d& pixel,
                                               Eigen::Matrix2d* J_floor_pixel) {
  // (a, b, c) = G (u, v, 1); c = 1 / depth, so c <= 0 means the ray meets the
  // floor plane behind the camera or never (on or above the horizon).
  const Eigen::Vector3d g = H_floor_img * pixel.homogeneous();
  const Eigen::Vector2d floor_point_m = g.hnormalized();
  if (!(g.z() > 0.0) || !floor_point_m.allFinite()) {
    std::ostringstream out;
    out << "pixel (" << pixel.x() << ", " << pixel.y()
        << ") is on or above the horizon: its ray does not meet the floor in front of the camera";
    return core::Status::Error(out.str());
  }
  if (J_floor_pixel != nullptr) {
    // d(a/c)/du = (G00 c - a G20) / c^2, and likewise for v and b.
    const double inv_c2 = 1.0 / (g.z() * g.z());
    for (int row = 0; row < 2; ++row) {
      for (int col = 0; col < 2; ++col) {
        (*J_floor_pixel)(row, col) =
            (H_floor_img(row, col) * g.z() - g(row) * H_floor_img(2, col)) * inv_c2;
      }
    }
  }
  return floor_point_m;
}

bool SameMount(const CameraMount& a, const CameraMount& b, double tolerance) {
  return std::abs(a.pitch_rad - b.pitch_rad) <= tolerance &&
         std::abs(a.roll_rad - b.roll_rad) <= tolerance &&
         std::abs(a.height_m - b.height_m) <= tolerance &&
         std::abs(a.yaw_rad - b.yaw_rad) <= tolerance &&
         std::abs(a.forward_m - b.forward_m) <= tolerance &&
         std::abs(a.lateral_m - b.lateral_m) <= tolerance;
}

}  // namespace groundline::calibration
