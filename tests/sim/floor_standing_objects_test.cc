// Things standing on the floor: clutter beside the route stays out of the
// vehicle's way and off the markings; the truth's floor segments of an
// object's edges are where the rendered image puts them; the world's static
// obstacles become occluders near the vehicle.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/sim/floor_camera.h"
#include "groundline/sim/floor_nuisances.h"
#include "groundline/sim/world.h"

namespace groundline::sim {
namespace {

// A drive along x for 40 m, then a quarter turn to the left and 20 m along y.
core::Trajectory LDrive() {
  core::Trajectory route;
  double t = 0.0;
  const auto at = [&](double x, double y, double yaw) {
    core::StampedPose p;
    p.stamp_s = t += 0.1;
    p.pose = core::SE2(x, y, yaw);
    return p;
  };
  for (double x = 0.0; x <= 40.0; x += 0.1) route.push_back(at(x, 0.0, 0.0));
  for (double a = 0.0; a <= std::numbers::pi / 2; a += 0.02) {
    route.push_back(at(40.0 + 3.0 * std::sin(a), 3.0 - 3.0 * std::cos(a), a));
  }
  for (double y = 3.0; y <= 23.0; y += 0.1) {
    route.push_back(at(43.0, y, std::numbers::pi / 2));
  }
  return route;
}

TEST(FloorStandingObjects, ClutterStaysOutOfTheVehiclesWayAndOffTheMarkings) {
  World world;
  FloorMarking tape;  // a lane edge 0.9 m to the right of the straight
  tape.polyline_m = {Vector2(0, -0.9), Vector2(40, -0.9)};
  tape.width_m = 0.05;
  world.markings.push_back(tape);
  const core::Trajectory route = LDrive();
  FloorRenderOptions vehicle;
  const int added = AddRouteClutter(&world, route, 40.0, vehicle, 7);
  ASSERT_EQ(static_cast<int>(world.obstacles.size()), added);
  EXPECT_GT(added, 5);  // about 25 tries; some rejected

  // An independent check: points spread over each object's footprint lie
  // outside the vehicle's rectangle at every pose, and off the tape.
  int posts = 0;
  for (const Obstacle& ob : world.obstacles) {
    EXPECT_EQ(ob.kind, ObstacleKind::kPallet);
    EXPECT_GT(ob.z_max_m, ob.z_min_m);
    if (ob.box.half_extent_m.maxCoeff() < 0.1) ++posts;
    for (double fx = -1.0; fx <= 1.0; fx += 0.25) {
      for (double fy = -1.0; fy <= 1.0; fy += 0.25) {
        const Vector2 p = core::SE2(ob.box.center_m, ob.box.yaw_rad) *
                          Vector2(fx * ob.box.half_extent_m.x(), fy * ob.box.half_extent_m.y());
        for (const core::StampedPose& pose : route) {
          const Vector2 local = pose.pose.Inverse() * p;
          const bool inside = local.x() <= vehicle.vehicle_front_m &&
                              local.x() >= vehicle.vehicle_back_m &&
                              std::abs(local.y()) <= vehicle.vehicle_half_width_m;
          ASSERT_FALSE(inside) << "clutter at " << ob.box.center_m.transpose();
        }
        if (p.x() > 0.0 && p.x() < 40.0) {
          EXPECT_GT(std::abs(p.y() + 0.9), 0.025);
        }
      }
    }
    // Beside the route: within reach of the camera's view to the side.
    double nearest = 1e9;
    for (const core::StampedPose& pose : route) {
      nearest = std::min(nearest, (pose.pose.translation() - ob.box.center_m).norm());
    }
    EXPECT_LT(nearest, 2.6);
  }
  EXPECT_GT(posts, 0);
  // The same seed places the same clutter.
  World again;
  again.markings = world.markings;
  EXPECT_EQ(AddRouteClutter(&again, route, 40.0, vehicle, 7), added);
  EXPECT_EQ(again.obstacles.back().box.center_m, world.obstacles.back().box.center_m);
}

TEST(FloorStandingObjects, VerticalEdgesLieOnRaysFromTheCamerasFootPoint) {
  Occluder box;  // 0.4 x 0.2 m, 0.5 m high, 2 m ahead and 1 m to the left
  box.footprint_m.center_m = Vector2(2.0, 1.0);
  box.footprint_m.half_extent_m = Vector2(0.2, 0.1);
  box.z_max_m = 0.5;
  const Eigen::Vector3d camera(0.5, 0.0, 1.0);
  const std::vector<NuisanceSegment> segments =
      StandingObjectSegments({box}, camera, core::SE2(), 8.0);
  ASSERT_EQ(segments.size(), 12u);  // 4 base edges, 4 vertical edges, 4 top edges
  int vertical = 0;
  for (const NuisanceSegment& s : segments) {
    EXPECT_EQ(s.cls, NuisanceClass::kStandingObject);
    const Vector2 ra = s.a_m - camera.head<2>(), rb = s.b_m - camera.head<2>();
    if (std::abs(ra.x() * rb.y() - ra.y() * rb.x()) > 1e-9) continue;
    ++vertical;
    // Similar triangles: a top at z seen from height h lands at h / (h - z)
    // times the foot's distance from the camera's foot point.
    EXPECT_NEAR(rb.norm(), ra.norm() * 1.0 / (1.0 - 0.5), 1e-9);
  }
  EXPECT_EQ(vertical, 4);

  // A post taller than the camera: its edges run out to the reach, and its
  // top has no floor image.
  Occluder post = box;
  post.footprint_m.half_extent_m = Vector2(0.05, 0.05);
  post.z_max_m = 2.0;
  const std::vector<NuisanceSegment> tall =
      StandingObjectSegments({post}, camera, core::SE2(), 8.0);
  EXPECT_EQ(tall.size(), 8u);
  int to_reach = 0;
  for (const NuisanceSegment& s : tall) {
    if ((s.b_m - camera.head<2>()).norm() > 7.9) {
      ++to_reach;
      EXPECT_NEAR((s.b_m - camera.head<2>()).norm(), 8.0, 1e-9);
    }
  }
  EXPECT_EQ(to_reach, 4);

  // In base_link: the same segments turned with the vehicle.
  const core::SE2 T_map_base(3.0, 4.0, 0.8);
  Occluder moved = box;
  moved.footprint_m.center_m = T_map_base * box.footprint_m.center_m;
  moved.footprint_m.yaw_rad = 0.8;
  const Vector2 cam_map = T_map_base * camera.head<2>();
  const std::vector<NuisanceSegment> in_base = StandingObjectSegments(
      {moved}, Eigen::Vector3d(cam_map.x(), cam_map.y(), camera.z()), T_map_base, 8.0);
  ASSERT_EQ(in_base.size(), segments.size());
  for (std::size_t k = 0; k < segments.size(); ++k) {
    EXPECT_LT((in_base[k].a_m - segments[k].a_m).norm(), 1e-9);
    EXPECT_LT((in_base[k].b_m - segments[k].b_m).norm(), 1e-9);
  }
}

TEST(FloorStandingObjects, TheRenderedObjectCoversTheFloorBetweenItsEdgeSegments) {
  FloorCameraOptions camera_options;
  camera_options.width_px = 320;
  camera_options.height_px = 256;
  camera_options.focal_px = 283.0;
  const calibration::CameraModel camera = *camera_options.MakeCameraModel();
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  options.occlusion = true;
  options.concrete_reflectance = 0.6;
  World world;
  world.floor_min_m = Vector2(-50, -50);
  world.floor_max_m = Vector2(50, 50);
  const FloorRenderer renderer =
      *FloorRenderer::Create(world, camera, camera_options.mount, options);
  const core::SE2 T_map_base(1.0, 2.0, 0.3);
  Occluder post;  // a 10 cm post 1.4 m ahead, 0.35 m to the left
  post.footprint_m.center_m = T_map_base * Vector2(1.4, 0.35);
  post.footprint_m.half_extent_m = Vector2(0.05, 0.05);
  post.footprint_m.yaw_rad = 0.3;
  post.z_max_m = 3.0;
  post.texture = 0.1;
  const GreyImage image = renderer.Render(T_map_base, {}, 0, {post});

  const Eigen::Isometry3d T_base_cam = calibration::BaseFromCamera(camera_options.mount);
  const Vector2 foot_base(T_base_cam.translation().x(), T_base_cam.translation().y());
  const Vector2 foot_map = T_map_base * foot_base;
  const std::vector<NuisanceSegment> segments = StandingObjectSegments(
      {post}, Eigen::Vector3d(foot_map.x(), foot_map.y(), T_base_cam.translation().z()), T_map_base,
      8.0);
  // The floor point (base_link) seen at a pixel, through the camera model.
  const auto pixel_of = [&](const Vector2& p_base) -> std::optional<Eigen::Vector2d> {
    const Eigen::Vector3d p_cam = T_base_cam.inverse() * Eigen::Vector3d(p_base.x(), p_base.y(), 0);
    if (p_cam.z() <= 0.0) return std::nullopt;
    const core::Result<Eigen::Vector2d> px = camera.Project(p_cam);
    if (!px.ok() || !camera.InImage(*px)) return std::nullopt;
    return *px;
  };
  // The two vertical-edge segments farthest apart in angle bound the post's
  // image on the floor: inside the wedge the post, outside it the floor.
  double lo = 1e9, hi = -1e9;
  for (const NuisanceSegment& s : segments) {
    const double angle = std::atan2((s.a_m - foot_base).y(), (s.a_m - foot_base).x());
    lo = std::min(lo, angle);
    hi = std::max(hi, angle);
  }
  const Vector2 base = T_map_base.Inverse() * post.footprint_m.center_m;
  const double r0 = (base - foot_base).norm();
  int inside = 0, outside = 0;
  for (double r = r0 + 0.15; r < r0 + 1.2; r += 0.1) {
    for (const auto& [angle, expect_post] :
         {std::pair{0.5 * (lo + hi), true}, std::pair{lo - 0.03, false},
          std::pair{hi + 0.03, false}}) {
      const Vector2 p = foot_base + r * Vector2(std::cos(angle), std::sin(angle));
      const std::optional<Eigen::Vector2d> px = pixel_of(p);
      if (!px) continue;
      const int value = image.at(static_cast<int>(px->x()), static_cast<int>(px->y()));
      if (expect_post) {
        ++inside;
        EXPECT_LT(value, 60) << "r " << r;  // the dark post (reflectance 0.12)
      } else {
        ++outside;
        EXPECT_GT(value, 100) << "r " << r;  // the bright floor
      }
    }
  }
  EXPECT_GT(inside, 4);
  EXPECT_GT(outside, 8);
}

TEST(FloorStandingObjects, StaticObstaclesNearTheVehicleBecomeOccluders) {
  World world;
  Obstacle upright;
  upright.kind = ObstacleKind::kRackUpright;
  upright.box = OrientedBox::FromMinMax(Vector2(2.0, 1.0), Vector2(2.1, 1.1));
  world.obstacles.push_back(upright);
  Obstacle wall = upright;
  wall.kind = ObstacleKind::kWall;
  wall.box = OrientedBox::FromMinMax(Vector2(30.0, -5.0), Vector2(30.2, 5.0));
  world.obstacles.push_back(wall);
  const std::vector<Occluder> near = StandingOccluders(world, Vector2(0, 0), 10.0);
  ASSERT_EQ(near.size(), 1u);  // the wall is 30 m away
  EXPECT_EQ(near[0].footprint_m.center_m, upright.box.center_m);
  EXPECT_GT(near[0].reflectance, 0.1);
  EXPECT_LT(near[0].reflectance, 0.3);                                   // dark painted steel
  EXPECT_EQ(StandingOccluders(world, Vector2(25, 0), 10.0).size(), 1u);  // now the wall
}

}  // namespace
}  // namespace groundline::sim
