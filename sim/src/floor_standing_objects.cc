// Things standing on the floor for the floor camera: the world's static
// obstacles as occluders, clutter beside the route, and where their edges fall
// on the floor in the camera's view (floor_nuisances.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "floor_camera_internal.h"
#include "groundline/core/segment_distance.h"
#include "groundline/sim/floor_nuisances.h"

namespace groundline::sim {
namespace {

// Diffuse reflectance seen by the camera (not the LiDAR's reflectivity):
// painted steel uprights and beams, wood, concrete and painted walls.
double CameraReflectance(ObstacleKind kind) {
  switch (kind) {
    case ObstacleKind::kRackUpright:
      return 0.18;
    case ObstacleKind::kRackBeam:
      return 0.35;
    case ObstacleKind::kPallet:
      return 0.45;
    case ObstacleKind::kWall:
    case ObstacleKind::kColumn:
      return 0.55;
    case ObstacleKind::kDockDoor:
      return 0.5;
    case ObstacleKind::kTrailer:
      return 0.4;
  }
  return 0.4;
}

// True if the two rectangles overlap (separating axis theorem).
bool BoxesOverlap(const OrientedBox& a, const OrientedBox& b) {
  const std::array<Vector2, 4> ca = a.Corners(), cb = b.Corners();
  for (const OrientedBox* box : {&a, &b}) {
    for (int k = 0; k < 2; ++k) {
      const double yaw = box->yaw_rad + k * std::numbers::pi / 2.0;
      const Vector2 axis(std::cos(yaw), std::sin(yaw));
      double a_lo = 1e300, a_hi = -1e300, b_lo = 1e300, b_hi = -1e300;
      for (int i = 0; i < 4; ++i) {
        a_lo = std::min(a_lo, ca[i].dot(axis));
        a_hi = std::max(a_hi, ca[i].dot(axis));
        b_lo = std::min(b_lo, cb[i].dot(axis));
        b_hi = std::max(b_hi, cb[i].dot(axis));
      }
      if (a_hi < b_lo || b_hi < a_lo) return false;
    }
  }
  return true;
}

// The floor point seen through p (above the floor, below the camera) from the
// camera at c: c + (p - c) * c.z / (c.z - p.z), clipped at reach_m from the
// camera's foot point; along the ray at reach_m when p is at or above it.
Vector2 FloorThrough(const Eigen::Vector3d& c, const Eigen::Vector3d& p, double reach_m) {
  const Vector2 foot = c.head<2>();
  const Vector2 dir = p.head<2>() - foot;
  const double norm = dir.norm();
  if (norm < 1e-9) return p.head<2>();
  const double r = p.z() < c.z() - 1e-9 ? norm * c.z() / (c.z() - p.z()) : reach_m;
  return foot + dir / norm * std::min(r, reach_m);
}

}  // namespace

std::vector<Occluder> StandingOccluders(const World& world, const Vector2& near_m,
                                        double radius_m) {
  std::vector<Occluder> out;
  for (std::size_t i = 0; i < world.obstacles.size(); ++i) {
    const Obstacle& ob = world.obstacles[i];
    if ((ob.box.center_m - near_m).norm() > radius_m + ob.box.BoundingRadius()) continue;
    const double jitter =
        0.75 + 0.5 * internal::HashU32(static_cast<std::int64_t>(i), 0, 0x0B5) / 4294967296.0;
    const double reflectance = ob.camera_reflectance >= 0.0
                                   ? ob.camera_reflectance
                                   : std::min(0.95, CameraReflectance(ob.kind) * jitter);
    out.push_back({ob.box, ob.z_min_m, ob.z_max_m, reflectance, 0.08});
  }
  return out;
}

std::vector<NuisanceSegment> StandingObjectSegments(const std::vector<Occluder>& occluders,
                                                    const Eigen::Vector3d& camera_map,
                                                    const core::SE2& T_map_base, double reach_m) {
  std::vector<NuisanceSegment> out;
  const core::SE2 T_base_map = T_map_base.Inverse();
  const auto add = [&](const Vector2& a, const Vector2& b) {
    if ((b - a).norm() < 1e-6) return;
    out.push_back({NuisanceClass::kStandingObject, T_base_map * a, T_base_map * b});
  };
  for (const Occluder& o : occluders) {
    if ((o.footprint_m.center_m - camera_map.head<2>()).norm() >
        reach_m + o.footprint_m.BoundingRadius()) {
      continue;
    }
    const std::array<Vector2, 4> c = o.footprint_m.Corners();
    std::array<Vector2, 4> base, top;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d bottom(c[k].x(), c[k].y(), o.z_min_m);
      const Eigen::Vector3d upper(c[k].x(), c[k].y(), o.z_max_m);
      base[k] = o.z_min_m <= 0.0 ? c[k] : FloorThrough(camera_map, bottom, reach_m);
      top[k] = FloorThrough(camera_map, upper, reach_m);
    }
    for (int k = 0; k < 4; ++k) {
      const int n = (k + 1) % 4;
      add(base[k], base[n]);
      add(base[k], top[k]);
      if (o.z_max_m < camera_map.z()) add(top[k], top[n]);
    }
  }
  return out;
}

int AddRouteClutter(World* world, const core::Trajectory& route, double per_100m,
                    const FloorRenderOptions& vehicle, std::uint64_t seed) {
  if (route.size() < 2 || per_100m <= 0.0) return 0;
  std::vector<double> arc(route.size(), 0.0);
  for (std::size_t k = 1; k < route.size(); ++k) {
    arc[k] = arc[k - 1] + (route[k].pose.translation() - route[k - 1].pose.translation()).norm();
  }
  std::mt19937_64 rng(seed * 0xA24BAED4963EE407ULL + 0xC1u);
  const auto u = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const auto n_try = static_cast<int>(std::lround(arc.back() / 100.0 * per_100m));
  constexpr double kMarginM = 0.1;
  OrientedBox body;  // the vehicle in base_link, with the margin
  body.center_m = Vector2(0.5 * (vehicle.vehicle_front_m + vehicle.vehicle_back_m), 0.0);
  body.half_extent_m = Vector2(0.5 * (vehicle.vehicle_front_m - vehicle.vehicle_back_m) + kMarginM,
                               vehicle.vehicle_half_width_m + kMarginM);
  const double body_radius = body.center_m.norm() + body.BoundingRadius();
  int added = 0;
  for (int t = 0; t < n_try; ++t) {
    const double s = u(0.0, arc.back());
    const auto k =
        static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin() - 1);
    const core::SE2& at = route[std::min(k, route.size() - 1)].pose;
    Obstacle ob;
    ob.kind = ObstacleKind::kPallet;
    ob.reflectivity = u(0.2, 0.7);
    const double kind = u(0.0, 1.0);
    Vector2 half;
    if (kind < 0.35) {  // a pallet, empty or loaded: wood, stretch-wrapped goods
      half = Vector2(0.6, 0.4);
      ob.z_max_m = u(0.0, 1.0) < 0.5 ? 0.144 : u(0.6, 1.6);
      ob.camera_reflectance = u(0.25, 0.7);
    } else if (kind < 0.7) {  // a box or a stack of boxes: cardboard, plastic crates
      // One draw per statement, y first (core::DrawVector's order).
      const double half_y = u(0.15, 0.45);
      half = Vector2(u(0.15, 0.45), half_y);
      ob.z_max_m = u(0.2, 1.2);
      ob.camera_reflectance = u(0.15, 0.6);
    } else {  // a post: a rack leg, a bollard, a barrier's upright; steel or yellow paint
      const double r = u(0.03, 0.07);
      half = Vector2(r, r);
      ob.z_max_m = u(0.8, 2.0);
      ob.camera_reflectance = u(0.0, 1.0) < 0.5 ? u(0.1, 0.25) : u(0.5, 0.8);
    }
    // Close beside the vehicle's path: the camera's view is narrow.
    const double side = u(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
    const double lateral =
        side * (vehicle.vehicle_half_width_m + kMarginM + half.norm() + u(0.02, 0.6));
    ob.box.center_m = at * Vector2(u(-1.0, 1.0), lateral);
    ob.box.half_extent_m = half;
    ob.box.yaw_rad = at.yaw() + (u(0.0, 1.0) < 0.7 ? u(-0.05, 0.05) : u(-1.5, 1.5));
    const double radius = ob.box.BoundingRadius();
    bool clear = true;
    for (std::size_t p = 0; p < route.size() && clear; ++p) {
      const core::SE2& pose = route[p].pose;
      if ((pose.translation() - ob.box.center_m).norm() > radius + body_radius) continue;
      OrientedBox placed = body;
      placed.center_m = pose * body.center_m;
      placed.yaw_rad = pose.yaw();
      clear = !BoxesOverlap(placed, ob.box);
    }
    for (std::size_t m = 0; m < world->markings.size() && clear; ++m) {
      const std::vector<Vector2>& line = world->markings[m].polyline_m;
      const double reach = radius + 0.5 * world->markings[m].width_m + kMarginM;
      for (std::size_t q = 0; q + 1 < line.size() && clear; ++q) {
        clear = core::DistanceToSegment(ob.box.center_m, line[q], line[q + 1]) > reach;
      }
    }
    if (!clear) continue;
    world->obstacles.push_back(ob);
    ++added;
  }
  return added;
}

}  // namespace groundline::sim
