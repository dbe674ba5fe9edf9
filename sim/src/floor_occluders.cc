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
    if (!m.PresentAt(stamp_s)) continue;
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

ImageCone ComputeImageCone(const calibration::CameraModel& camera, int w, int h) {
  ImageCone wide{-kMaxTanOffAxis, kMaxTanOffAxis, -kMaxTanOffAxis, kMaxTanOffAxis};
  // The border of the image widened by 4 px, every 8 px: under a monotonic
  // lens the image's extent in (x/z, y/z) is reached on its border.
  constexpr int kMargin = 4, kStep = 8;
  std::vector<Eigen::Vector2d> border;
  const int u0 = -kMargin, u1 = w - 1 + kMargin, v0 = -kMargin, v1 = h - 1 + kMargin;
  for (int u = u0; u <= u1; u += kStep) {
    border.emplace_back(u, v0);
    border.emplace_back(u, v1);
  }
  for (int v = v0; v <= v1; v += kStep) {
    border.emplace_back(u0, v);
    border.emplace_back(u1, v);
  }
  border.emplace_back(u1, v1);
  Eigen::Matrix2Xd pixels(2, static_cast<Eigen::Index>(border.size()));
  for (std::size_t k = 0; k < border.size(); ++k)
    pixels.col(static_cast<Eigen::Index>(k)) = border[k];
  Eigen::Matrix3Xd rays;
  std::vector<std::uint8_t> ok;
  if (camera.UnprojectBatch(pixels, calibration::RayNormalization::kZEqualsOne, &rays, &ok) !=
      static_cast<int>(border.size())) {
    return wide;
  }
  ImageCone c{rays.row(0).minCoeff(), rays.row(0).maxCoeff(), rays.row(1).minCoeff(),
              rays.row(1).maxCoeff()};
  // 10 % of the span on each side, within the projectable cone.
  const double mx = 0.1 * (c.x_hi - c.x_lo), my = 0.1 * (c.y_hi - c.y_lo);
  c.x_lo = std::max(c.x_lo - mx, wide.x_lo);
  c.x_hi = std::min(c.x_hi + mx, wide.x_hi);
  c.y_lo = std::max(c.y_lo - my, wide.y_lo);
  c.y_hi = std::min(c.y_hi + my, wide.y_hi);
  return c;
}

void DrawOccluders(const calibration::CameraModel& camera, const calibration::CameraMount& mount,
                   const ImageCone& cone, const core::SE2& T_map_base,
                   const std::vector<Occluder>& occluders, double gain, int w, int h,
                   std::vector<float>* dn) {
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
  // A box, face or quad is skipped when it cannot show: the result is the same
  // as projecting and filling every quad (a quad with a corner outside the
  // projectable cone is never drawn, and a quad entirely beyond one side of
  // the image fills no pixel), in a fraction of the time.
  const auto outside_cone = [](const Eigen::Vector3d& p) {
    return p.z() < kNearCamM || std::max(std::abs(p.x()), std::abs(p.y())) > kMaxTanOffAxis * p.z();
  };
  // Which sides of the image cone a point in front of the camera lies beyond
  // (bits); a quad whose corners share a bit lies wholly beyond that side.
  const auto outcode = [&cone](const Eigen::Vector3d& p) {
    return (p.x() > cone.x_hi * p.z() ? 1 : 0) | (p.x() < cone.x_lo * p.z() ? 2 : 0) |
           (p.y() > cone.y_hi * p.z() ? 4 : 0) | (p.y() < cone.y_lo * p.z() ? 8 : 0);
  };
  // Every point of a convex set beyond one of the cone's planes is beyond it.
  const auto all_outside_one_plane = [](const std::vector<Eigen::Vector3d>& pts) {
    const auto all = [&](auto&& pred) { return std::all_of(pts.begin(), pts.end(), pred); };
    return all([](const Eigen::Vector3d& p) { return p.z() < kNearCamM; }) ||
           all([](const Eigen::Vector3d& p) { return p.x() > kMaxTanOffAxis * p.z(); }) ||
           all([](const Eigen::Vector3d& p) { return -p.x() > kMaxTanOffAxis * p.z(); }) ||
           all([](const Eigen::Vector3d& p) { return p.y() > kMaxTanOffAxis * p.z(); }) ||
           all([](const Eigen::Vector3d& p) { return -p.y() > kMaxTanOffAxis * p.z(); });
  };
  // fillConvexPoly rounds vertices to the nearest pixel; a margin of 2 px
  // keeps every quad that could touch the image.
  const int lo_px = -(2 << kShift), hi_u = (w + 2) << kShift, hi_v = (h + 2) << kShift;
  std::vector<Eigen::Vector3d> vertex_cam;
  std::vector<int> vertex_code;      // outcode, or -1 outside the projectable cone
  std::vector<int> vertex_slot;      // column in the batch of projected vertices, or -1
  std::vector<cv::Point> vertex_px;  // by batch column
  std::vector<std::uint8_t> projected_ok;
  Eigen::Matrix3Xd batch;
  Eigen::Matrix2Xd batch_px;
  for (const Occluder* o : order) {
    // Cull boxes far outside the view (the camera sees a few metres ahead).
    if (distance(o) > 30.0 + o->footprint_m.BoundingRadius()) continue;
    const std::vector<Face> faces = BoxFaces(*o);
    std::vector<Eigen::Vector3d> box_cam;
    for (const Face& face : faces) {
      for (const Eigen::Vector3d& c : face.corners) box_cam.push_back(T_cam_map * c);
    }
    if (all_outside_one_plane(box_cam)) continue;
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
      // The face's grid of vertices; only those of quads that may show are
      // projected, each once, in one batch.
      const auto at = [nb](int i, int j) { return static_cast<std::size_t>(i) * (nb + 1) + j; };
      const std::size_t nv = static_cast<std::size_t>(na + 1) * (nb + 1);
      vertex_cam.resize(nv);
      vertex_code.resize(nv);
      vertex_slot.assign(nv, -1);
      for (int i = 0; i <= na; ++i) {
        for (int j = 0; j <= nb; ++j) {
          const Eigen::Vector3d p_cam =
              point(i / static_cast<double>(na), j / static_cast<double>(nb));
          vertex_cam[at(i, j)] = p_cam;
          vertex_code[at(i, j)] = outside_cone(p_cam) ? -1 : outcode(p_cam);
        }
      }
      const auto corners_of = [&](int i, int j) {
        return std::array<std::size_t, 4>{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      };
      const auto may_show = [&](const std::array<std::size_t, 4>& corner) {
        int common = ~0;
        for (const std::size_t c : corner) {
          if (vertex_code[c] < 0) return false;
          common &= vertex_code[c];
        }
        return common == 0;
      };
      int slots = 0;
      for (int i = 0; i < na; ++i) {
        for (int j = 0; j < nb; ++j) {
          const std::array<std::size_t, 4> corner = corners_of(i, j);
          if (!may_show(corner)) continue;
          for (const std::size_t c : corner) {
            if (vertex_slot[c] < 0) vertex_slot[c] = slots++;
          }
        }
      }
      if (slots == 0) continue;
      batch.resize(3, slots);
      for (std::size_t c = 0; c < nv; ++c) {
        if (vertex_slot[c] >= 0) batch.col(vertex_slot[c]) = vertex_cam[c];
      }
      camera.ProjectBatch(batch, &batch_px, &projected_ok);
      vertex_px.resize(static_cast<std::size_t>(slots));
      for (int k = 0; k < slots; ++k) {
        const Eigen::Vector2d px = batch_px.col(k);
        if (!projected_ok[static_cast<std::size_t>(k)] || !px.allFinite() ||
            px.cwiseAbs().maxCoeff() > 1e5) {
          projected_ok[static_cast<std::size_t>(k)] = 0;
          continue;
        }
        vertex_px[static_cast<std::size_t>(k)] =
            cv::Point(static_cast<int>(std::lround(px.x() * (1 << kShift))),
                      static_cast<int>(std::lround(px.y() * (1 << kShift))));
      }
      for (int i = 0; i < na; ++i) {
        for (int j = 0; j < nb; ++j) {
          const std::array<std::size_t, 4> corner = corners_of(i, j);
          if (!may_show(corner)) continue;
          std::array<cv::Point, 4> quad;
          bool ok = true;
          for (int k = 0; k < 4 && ok; ++k) {
            const auto slot = static_cast<std::size_t>(vertex_slot[corner[k]]);
            ok = projected_ok[slot] != 0;
            quad[k] = vertex_px[slot];
          }
          if (!ok) continue;
          const auto [u_lo, u_hi] = std::minmax({quad[0].x, quad[1].x, quad[2].x, quad[3].x});
          const auto [v_lo, v_hi] = std::minmax({quad[0].y, quad[1].y, quad[2].y, quad[3].y});
          if (u_hi < lo_px || v_hi < lo_px || u_lo > hi_u || v_lo > hi_v) continue;
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
