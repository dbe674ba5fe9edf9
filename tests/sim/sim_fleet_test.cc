// Fleet runs: one world, a dataset per robot, the robots kept apart, and
// each robot's LiDAR sees the others where their boxes are.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "groundline/sim/lidar.h"
#include "groundline/sim/sim_run.h"

namespace groundline::sim {
namespace {

// Distance along the ray to the box's boundary (infinity if missed), by the
// slab method in the box's frame; independent of the LiDAR's own geometry code.
double RayBoxDistance(const Vector2& origin, const Vector2& dir, const OrientedBox& box) {
  const double c = std::cos(box.yaw_rad), s = std::sin(box.yaw_rad);
  const Vector2 d = origin - box.center_m;
  const Vector2 o(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
  const Vector2 u(c * dir.x() + s * dir.y(), -s * dir.x() + c * dir.y());
  double t0 = -std::numeric_limits<double>::infinity();
  double t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 2; ++a) {
    const double h = box.half_extent_m[a];
    if (std::abs(u[a]) < 1e-12) {
      if (std::abs(o[a]) > h) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (-h - o[a]) / u[a], tb = (h - o[a]) / u[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1 || t0 < 0.0) return std::numeric_limits<double>::infinity();
  return t0;
}

SimRunOptions SmallCorridors() {
  SimRunOptions o;
  o.zone = Zone::kD;
  o.seed = 3;
  o.zone_d.corridor_length_m = 60.0;
  o.zone_d.num_cross_corridors = 3;
  o.zone_d.num_forklifts = 0;
  o.zone_d.num_pedestrians = 0;
  o.route.length_m = 120.0;
  o.with_camera = false;
  o.lidar.rate_hz = 2.0;
  o.lidar.range_noise_sigma_m = 0.0;
  o.lidar.dropout_probability = 0.0;
  return o;
}

TEST(SimFleet, EachRobotHasItsRunAndSeesTheOthersBoxes) {
  SimRunOptions options = SmallCorridors();
  // Corridors without passing lanes: on many seeds three robots cannot all
  // be scheduled (fleet_traffic.h); this one can.
  options.seed = 6;
  FleetOptions fleet;
  fleet.robots = 3;
  const core::Result<std::vector<SimRun>> runs = SimulateFleet(options, fleet);
  ASSERT_TRUE(runs.ok()) << runs.message();
  ASSERT_EQ(runs->size(), 3u);
  // Own routes (different starts), one floor map, names per robot.
  for (std::size_t k = 0; k < 3; ++k) {
    const SimRun& r = (*runs)[k];
    EXPECT_NEAR(r.route.length_m, 120.0, 1e-6);
    EXPECT_EQ(r.dataset.manifest.provenance.at("robot"), std::to_string(k));
    EXPECT_EQ(r.world.moving.size(), 2u);  // the other two robots
    EXPECT_EQ(r.dataset.floor_map->markings.size(), (*runs)[0].dataset.floor_map->markings.size());
    if (k > 0) {
      EXPECT_GT((r.route.T_map_base.front().pose.translation() -
                 (*runs)[0].route.T_map_base.front().pose.translation())
                    .norm(),
                1.0);
    }
  }
  // Kept apart (fleet_traffic.h): every pair, while both are on the floor.
  for (std::size_t j = 0; j < 3; ++j) {
    for (std::size_t k = j + 1; k < 3; ++k) {
      const Separation closest =
          MinimumSeparation((*runs)[k].route.T_map_base, (*runs)[j].route.T_map_base);
      EXPECT_GE(closest.distance_m, 0.9 * fleet.traffic.separation_m)
          << "robots " << j << " and " << k << " at " << closest.stamp_s << " s";
    }
  }
  // Robot 0 with a single-robot run of the same options: same route.
  const core::Result<SimRun> alone = SimulateRun(options);
  ASSERT_TRUE(alone.ok());
  EXPECT_EQ(alone->route.waypoints_m, (*runs)[0].route.waypoints_m);

  // Every beam of robot 0 whose ray meets another robot's box returns no
  // farther than the box, and where the static world (the same LiDAR without
  // the robots) is farther, exactly at the box.
  const SimRun& r0 = (*runs)[0];
  const double dt = options.lidar.TimeIncrementS();
  World empty = r0.world;
  empty.moving.clear();
  const PlanarLidar static_lidar(empty, options.lidar);
  int exact = 0, checked = 0, in_front = 0;
  for (std::size_t k = 0; k < r0.dataset.scans.size(); ++k) {
    const core::LaserScan& scan = r0.dataset.scans[k];
    // Dataset scans are stamped at mid-sweep; the simulator's at the first ray.
    const double first_ray_s =
        scan.stamp_s - 0.5 * static_cast<double>(scan.ranges_m.size() - 1) * dt;
    const LaserScan walls = static_lidar.ScanAlong(r0.route.T_map_base, first_ray_s, k);
    std::vector<OrientedBox> boxes;
    for (const MovingObstacle& m : r0.world.moving) {
      if (m.PresentAt(first_ray_s)) boxes.push_back(m.FootprintAt(first_ray_s));
    }
    for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
      const core::SE2 T_map_lidar =
          InterpolatePose(r0.route.T_map_base, first_ray_s + static_cast<double>(i) * dt) *
          options.lidar.T_base_lidar;
      const double angle = T_map_lidar.yaw() + scan.BeamAngle_rad(i);
      const Vector2 dir(std::cos(angle), std::sin(angle));
      double box_m = std::numeric_limits<double>::infinity();
      for (const OrientedBox& b : boxes) {
        box_m = std::min(box_m, RayBoxDistance(T_map_lidar.translation(), dir, b));
      }
      if (!(box_m < scan.range_max_m) || box_m < scan.range_min_m) continue;
      ++checked;
      ASSERT_TRUE(scan.IsReturn(i)) << "beam " << i << " at " << scan.stamp_s << " s";
      EXPECT_LE(scan.ranges_m[i], box_m + 1e-3);
      if (!(walls.ranges_m[i] > box_m + 1e-3)) continue;  // a wall hides the robot
      ++in_front;
      if (std::abs(scan.ranges_m[i] - box_m) < 1e-3) ++exact;
    }
  }
  EXPECT_GT(checked, 50);
  EXPECT_GT(in_front, 50);
  EXPECT_EQ(exact, in_front);
}

TEST(SimFleet, InvalidFleetOptionsNameTheField) {
  FleetOptions fleet;
  fleet.robots = 0;
  const core::Result<std::vector<SimRun>> runs = SimulateFleet(SmallCorridors(), fleet);
  ASSERT_FALSE(runs.ok());
  EXPECT_NE(runs.message().find("robots"), std::string::npos) << runs.message();
}

}  // namespace
}  // namespace groundline::sim
