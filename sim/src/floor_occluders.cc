// Occluders in front of the floor camera, drawn by forward projection
// (floor_camera.h, step 4).
#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "floor_camera_internal.h"

namespace groundline::sim {

std::vector<Occluder> OccludersAt(const World& world, double stamp_s) {
  std::vector<Occluder> out;
  out.reserve(world.moving.size());
  for (const MovingObstacle& m : world.moving) {
    out.push_back({m.FootprintAt(stamp_s), m.z_min_m, m.z_max_m, 0.12});
  }
  return out;
}

namespace internal {
namespace {

// Faces are drawn as a grid of quads, at least 16 a side and at most 0.2 m
// apart (a long wall keeps its quads small enough to be projected whole).
constexpr int kMinFaceDivisions = 16;
constexpr int kMaxFaceDivisions = 512;
constexpr double kMaxQuadM = 0.2;
// Corners farther off the optical axis than this (tan of ~72 deg) are not
// projected: the lens polynomial is not meant for them.
constexpr double kMaxTanOffAxis = 3.0;
constexpr double kNearCamM = 0.02;
constexpr double kSideShade = 0.6;

struct Face {
  std::array<Eigen::Vector3d, 4> corners;  // map frame, in order around the face
  Eigen::Vector3d normal;                  // outward
  double shade = 1.0;
};

std::vector<Face> BoxFaces(const Occluder& o) {
  const std::array<Vector2, 4> c = o.footprint_m.Corners();  // counter-clockwise
  const auto at = [&](int k, double z) { return Eigen::Vector3d(c[k].x(), c[k].y(), z); };
  std::vector<Face> faces;
  faces.push_back({{at(0, o.z_max_m), at(1, o.z_max_m), at(2, o.z_max_m), at(3, o.z_max_m)},
                   Eigen::Vector3d::UnitZ(),
                   1.0});
  faces.push_back({{at(0, o.z_min_m), at(3, o.z_min_m), at(2, o.z_min_m), at(1, o.z_min_m)},
                   -Eigen::Vector3d::UnitZ(),
                   kSideShade});
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    const Vector2 edge = c[n] - c[k];
    const Eigen::Vector3d normal(edge.y(), -edge.x(), 0.0);  // outward for CCW corners
    faces.push_back({{at(k, o.z_min_m), at(n, o.z_min_m), at(n, o.z_max_m), at(k, o.z_max_m)},
                     normal.normalized(),
                     kSideShade});
  }
  return faces;
}

}  // namespace

void DrawOccluders(const calibration::CameraModel& camera, const calibration::CameraMount& mount,
                   const core::SE2& T_map_base, const std::vector<Occluder>& occluders, double gain,
                   int w, int h, std::vector<float>* dn) {
  Eigen::Isometry3d T_map_base3 = Eigen::Isometry3d::Identity();
  T_map_base3.linear().topLeftCorner<2, 2>() = T_map_base.Rotation();
  T_map_base3.translation().head<2>() = T_map_base.translation();
  const Eigen::Isometry3d T_cam_map = (T_map_base3 * calibration::BaseFromCamera(mount)).inverse();
  const Eigen::Vector3d camera_map = T_cam_map.inverse().translation();

  // Farthest first: a nearer box paints over a farther one.
  std::vector<const Occluder*> order;
  for (const Occluder& o : occluders) order.push_back(&o);
  const auto distance = [&](const Occluder* o) {
    return (o->footprint_m.center_m - camera_map.head<2>()).norm();
  };
  std::sort(order.begin(), order.end(),
            [&](const Occluder* a, const Occluder* b) { return distance(a) > distance(b); });

  cv::Mat image(h, w, CV_32FC1, dn->data());
  constexpr int kShift = 4;  // sub-pixel vertices for cv::fillConvexPoly
  const auto divisions = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::clamp(static_cast<int>(std::ceil((b - a).norm() / kMaxQuadM)), kMinFaceDivisions,
                      kMaxFaceDivisions);
  };
  for (const Occluder* o : order) {
    // Cull boxes far outside the view (the camera sees a few metres ahead).
    if (distance(o) > 30.0 + o->footprint_m.BoundingRadius()) continue;
    const std::vector<Face> faces = BoxFaces(*o);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const Face& face = faces[f];
      if (face.normal.dot(camera_map - face.corners[0]) <= 0.0) continue;  // faces away
      const double value = gain * o->reflectance * face.shade;
      const int na = divisions(face.corners[0], face.corners[1]);
      const int nb = divisions(face.corners[0], face.corners[3]);
      // The texture's patches are seeded by the box's centre, so that a box
      // looks the same in every frame whatever the drawing order.
      const auto patch_seed = static_cast<std::uint32_t>(HashU32(
          std::llround(o->footprint_m.center_m.x() * 1000.0),
          std::llround(o->footprint_m.center_m.y() * 1000.0), static_cast<std::uint32_t>(f)));
      const auto point = [&](double a, double b) {
        const Eigen::Vector3d bottom = face.corners[0] + a * (face.corners[1] - face.corners[0]);
        const Eigen::Vector3d top = face.corners[3] + a * (face.corners[2] - face.corners[3]);
        return Eigen::Vector3d(T_cam_map * (bottom + b * (top - bottom)));
      };
      for (int i = 0; i < na; ++i) {
        for (int j = 0; j < nb; ++j) {
          std::array<cv::Point, 4> quad;
          bool ok = true;
          const double a[4] = {i + 0.0, i + 1.0, i + 1.0, i + 0.0};
          const double b[4] = {j + 0.0, j + 0.0, j + 1.0, j + 1.0};
          for (int k = 0; k < 4 && ok; ++k) {
            const Eigen::Vector3d p_cam = point(a[k] / na, b[k] / nb);
            if (p_cam.z() < kNearCamM ||
                std::max(std::abs(p_cam.x()), std::abs(p_cam.y())) > kMaxTanOffAxis * p_cam.z()) {
              ok = false;
              break;
            }
            const core::Result<Eigen::Vector2d> px = camera.Project(p_cam);
            if (!px.ok() || !px->allFinite() || px->cwiseAbs().maxCoeff() > 1e5) {
              ok = false;
              break;
            }
            quad[k] = cv::Point(static_cast<int>(std::lround(px->x() * (1 << kShift))),
                                static_cast<int>(std::lround(px->y() * (1 << kShift))));
          }
          if (!ok) continue;
          const double patch =
              o->texture > 0.0 ? 1.0 + o->texture * (HashU32(i, j, patch_seed) / 2147483648.0 - 1.0)
                               : 1.0;
          cv::fillConvexPoly(image, quad.data(), 4, cv::Scalar(value * patch), cv::LINE_8, kShift);
        }
      }
    }
  }
}

}  // namespace internal
}  // namespace groundline::sim
