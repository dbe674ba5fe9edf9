// Occluders in front of the floor camera: the pixels they cover are the
// pixels whose viewing ray meets the box before the floor (an independent ray
// cast through the camera model's unprojection).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "groundline/sim/floor_camera.h"
#include "groundline/sim/world.h"

namespace groundline::sim {
namespace {

// Distance along the ray (origin o, unit direction d, map frame) to the box,
// infinity if missed (slab method in the box's frame).
double RayBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Occluder& box) {
  const double c = std::cos(box.footprint_m.yaw_rad), s = std::sin(box.footprint_m.yaw_rad);
  const Eigen::Vector2d rel = o.head<2>() - box.footprint_m.center_m;
  const Eigen::Vector3d ol(c * rel.x() + s * rel.y(), -s * rel.x() + c * rel.y(),
                           o.z() - 0.5 * (box.z_min_m + box.z_max_m));
  const Eigen::Vector3d dl(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z());
  const Eigen::Vector3d half(box.footprint_m.half_extent_m.x(), box.footprint_m.half_extent_m.y(),
                             0.5 * (box.z_max_m - box.z_min_m));
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(dl[a]) < 1e-12) {
      if (std::abs(ol[a]) > half[a]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (-half[a] - ol[a]) / dl[a], tb = (half[a] - ol[a]) / dl[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}

// Renders the boxes over a bright floor and compares the dark pixels with the
// ray-cast mask, away from the outlines; the counts for the caller's bounds.
struct MaskComparison {
  int occluded = 0;         // pixels whose ray meets a box first
  int compared = 0;         // floor pixels away from an outline
  int wrong = 0;            // dark where not occluded, or bright where occluded
  int changed_outside = 0;  // not occluded, yet different from the clear render
};

MaskComparison CompareWithRayCast(const core::SE2& T_map_base, const std::vector<Occluder>& boxes) {
  FloorCameraOptions camera_options;  // a quarter-size imager keeps the test fast
  camera_options.width_px = 320;
  camera_options.height_px = 256;
  camera_options.focal_px = 283.0;
  const calibration::CameraModel camera = *camera_options.MakeCameraModel();
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  options.occlusion = true;
  options.concrete_reflectance = 0.6;  // bright floor, dark box
  World world;
  world.floor_min_m = Vector2(-50, -50);
  world.floor_max_m = Vector2(50, 50);
  const FloorRenderer renderer =
      *FloorRenderer::Create(world, camera, camera_options.mount, options);
  const GreyImage image = renderer.Render(T_map_base, {}, 0, boxes);
  const GreyImage clear = renderer.Render(T_map_base, {}, 0, {});

  // The expected mask: the ray meets a box before the floor.
  Eigen::Isometry3d T_map_base3 = Eigen::Isometry3d::Identity();
  T_map_base3.linear().topLeftCorner<2, 2>() = T_map_base.Rotation();
  T_map_base3.translation().head<2>() = T_map_base.translation();
  const Eigen::Isometry3d T_map_cam =
      T_map_base3 * calibration::BaseFromCamera(camera_options.mount);
  const int w = camera_options.width_px, h = camera_options.height_px;
  std::vector<int> expected(static_cast<std::size_t>(w) * h, 0);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3d d = T_map_cam.linear() * *camera.Unproject(Eigen::Vector2d(u, v));
      const Eigen::Vector3d o = T_map_cam.translation();
      const double floor_t = d.z() < 0.0 ? -o.z() / d.z() : std::numeric_limits<double>::infinity();
      for (const Occluder& b : boxes) {
        if (RayBox(o, d, b) < floor_t) expected[static_cast<std::size_t>(v) * w + u] = 1;
      }
    }
  }
  MaskComparison m;
  for (int v = 1; v + 1 < h; ++v) {
    for (int u = 1; u + 1 < w; ++u) {
      const int e = expected[static_cast<std::size_t>(v) * w + u];
      bool interior = true;  // all 8 neighbours agree: away from the outline
      for (int dv = -1; dv <= 1; ++dv) {
        for (int du = -1; du <= 1; ++du) {
          interior = interior && expected[static_cast<std::size_t>(v + dv) * w + u + du] == e;
        }
      }
      m.occluded += e;
      if (!interior || clear.at(u, v) < 120) continue;  // outline, or not floor anyway
      ++m.compared;
      const bool dark = image.at(u, v) < 60;
      if (dark != (e == 1)) ++m.wrong;
      if (e == 0 && image.at(u, v) != clear.at(u, v)) ++m.changed_outside;
    }
  }
  return m;
}

TEST(FloorCameraOcclusion, OccludedPixelsAreWhereTheBoxProjects) {
  const core::SE2 T_map_base(3.0, -2.0, 0.7);
  // A pallet-sized box 1.3-1.9 m ahead, across the view, turned by 20 deg,
  // and a thin pole (a pedestrian's leg) beside it.
  std::vector<Occluder> boxes(2);
  boxes[0].footprint_m.center_m = T_map_base * Vector2(1.6, 0.05);
  boxes[0].footprint_m.half_extent_m = Vector2(0.3, 0.25);
  boxes[0].footprint_m.yaw_rad = T_map_base.yaw() + 0.35;
  boxes[0].z_max_m = 0.4;
  boxes[1].footprint_m.center_m = T_map_base * Vector2(1.2, -0.45);
  boxes[1].footprint_m.half_extent_m = Vector2(0.06, 0.06);
  boxes[1].z_max_m = 1.8;
  const MaskComparison m = CompareWithRayCast(T_map_base, boxes);
  EXPECT_GT(m.occluded, 2000);  // the box covers a good part of the view
  EXPECT_GT(m.compared, 40000);
  EXPECT_EQ(m.wrong, 0);
  EXPECT_EQ(m.changed_outside, 0);
}

// The renderer skips boxes, faces and quads that cannot show. A long rack face
// running from behind the vehicle to far ahead crosses the image's border and
// most of it lies outside the view: its visible part must still be drawn up
// to the border, and a box behind the camera must leave the image untouched.
TEST(FloorCameraOcclusion, ABoxCrossingTheImageBorderIsDrawnUpToIt) {
  const core::SE2 T_map_base(-4.0, 7.0, -0.4);
  std::vector<Occluder> boxes(2);
  boxes[0].footprint_m.center_m = T_map_base * Vector2(4.0, 0.9);  // -8 m .. +16 m, to the left
  boxes[0].footprint_m.half_extent_m = Vector2(12.0, 0.25);
  boxes[0].footprint_m.yaw_rad = T_map_base.yaw();
  boxes[0].z_max_m = 3.0;
  boxes[1].footprint_m.center_m = T_map_base * Vector2(-2.0, 0.0);  // behind
  boxes[1].footprint_m.half_extent_m = Vector2(0.4, 0.4);
  boxes[1].z_max_m = 1.0;
  const MaskComparison m = CompareWithRayCast(T_map_base, boxes);
  EXPECT_GT(m.occluded, 1000);
  EXPECT_GT(m.compared, 30000);
  EXPECT_EQ(m.wrong, 0);
  EXPECT_EQ(m.changed_outside, 0);
}

TEST(FloorCameraOcclusion, OccludersOfTheWorldFollowItsMovingObstacles) {
  World world;
  MovingObstacle forklift;
  forklift.path_m = {Vector2(0, 0), Vector2(10, 0)};
  forklift.speed_mps = 2.0;
  world.moving.push_back(forklift);
  const std::vector<Occluder> at_1s = OccludersAt(world, 1.0);
  ASSERT_EQ(at_1s.size(), 1u);
  EXPECT_NEAR(at_1s[0].footprint_m.center_m.x(), 2.0, 1e-9);
  EXPECT_EQ(at_1s[0].z_max_m, forklift.z_max_m);
}

}  // namespace
}  // namespace groundline::sim
