#include "groundline/sim/route.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "groundline/sim/zones.h"
#include "route_internal.h"

namespace groundline::sim {
namespace {

// Distance from a point to an oriented box (0 inside), brute force and
// independent of the spatial index the generator uses.
double DistanceToBox(const Vector2& p, const OrientedBox& box) {
  const double c = std::cos(box.yaw_rad);
  const double s = std::sin(box.yaw_rad);
  const Vector2 d = p - box.center_m;
  const double u = std::abs(c * d.x() + s * d.y()) - box.half_extent_m.x();
  const double v = std::abs(-s * d.x() + c * d.y()) - box.half_extent_m.y();
  return Vector2(std::max(u, 0.0), std::max(v, 0.0)).norm();
}

class RouteInZone : public ::testing::TestWithParam<std::tuple<Zone, std::uint64_t>> {};

TEST_P(RouteInZone, StaysInFreeSpaceWithTheRequestedLengthSpeedsAndCurvature) {
  const auto [zone, seed] = GetParam();
  const core::Result<World> world = BuildZone(zone, seed);
  ASSERT_TRUE(world.ok()) << world.message();
  RouteOptions options;
  options.seed = seed;
  options.closed_loop = true;
  const core::Result<Route> route = GenerateRoute(*world, options);
  ASSERT_TRUE(route.ok()) << route.message();
  EXPECT_TRUE(route->closed_loop);
  const core::Trajectory& traj = route->T_map_base;
  ASSERT_GT(traj.size(), 1000u);
  ASSERT_EQ(route->speed_mps.size(), traj.size());
  ASSERT_EQ(route->yaw_rate_radps.size(), traj.size());

  // Length within the tolerance; the samples trace that length.
  EXPECT_NEAR(route->length_m, options.length_m,
              options.length_tolerance_fraction * options.length_m);
  double traced_m = 0.0;
  for (std::size_t k = 1; k < traj.size(); ++k) {
    traced_m += (traj[k].pose.translation() - traj[k - 1].pose.translation()).norm();
  }
  traced_m += (traj.front().pose.translation() - traj.back().pose.translation()).norm();
  EXPECT_NEAR(traced_m, route->length_m, 1e-3 * route->length_m);

  // Clearance: every other sample (at most 4 cm apart) against every obstacle
  // at any height, brute force over 4 m buckets of the boxes' bounding rectangles.
  constexpr double kBucketM = 4.0;
  auto bucket = [&](double v) { return static_cast<int>(std::floor(v / kBucketM)); };
  std::map<std::pair<int, int>, std::vector<const Obstacle*>> buckets;
  for (const Obstacle& o : world->obstacles) {
    Vector2 lo = o.box.Corners()[0], hi = lo;
    for (const Vector2& c : o.box.Corners()) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
    for (int i = bucket(lo.x()); i <= bucket(hi.x()); ++i) {
      for (int j = bucket(lo.y()); j <= bucket(hi.y()); ++j) buckets[{i, j}].push_back(&o);
    }
  }
  double min_clearance_m = 1e9;
  for (std::size_t k = 0; k < traj.size(); k += 2) {
    const Vector2 p = traj[k].pose.translation();
    const int bi = bucket(p.x());
    const int bj = bucket(p.y());
    for (int i = bi - 1; i <= bi + 1; ++i) {
      for (int j = bj - 1; j <= bj + 1; ++j) {
        const auto it = buckets.find({i, j});
        if (it == buckets.end()) continue;
        for (const Obstacle* o : it->second) {
          min_clearance_m = std::min(min_clearance_m, DistanceToBox(p, o->box));
        }
      }
    }
  }
  EXPECT_GE(min_clearance_m - options.vehicle_half_width_m, options.min_clearance_m - 1e-9);
  EXPECT_GE(route->min_clearance_m, options.min_clearance_m);

  // Uniform stamps; speeds in [1, 2] m/s; bounded curvature, acceleration and
  // angular acceleration; the heading follows the motion.
  const double dt = 1.0 / options.sample_rate_hz;
  double max_curvature = 0.0, max_accel = 0.0, max_yaw_accel = 0.0, max_heading_error = 0.0;
  for (std::size_t k = 0; k < traj.size(); ++k) {
    EXPECT_NEAR(traj[k].stamp_s, options.start_stamp_s + k * dt, 1e-9);
    EXPECT_GE(route->speed_mps[k], options.min_speed_mps - 1e-9);
    EXPECT_LE(route->speed_mps[k], options.max_speed_mps + 1e-9);
    max_curvature =
        std::max(max_curvature, std::abs(route->yaw_rate_radps[k] / route->speed_mps[k]));
    if (k == 0) continue;
    max_accel = std::max(max_accel, std::abs(route->speed_mps[k] - route->speed_mps[k - 1]) / dt);
    max_yaw_accel = std::max(
        max_yaw_accel, std::abs(route->yaw_rate_radps[k] - route->yaw_rate_radps[k - 1]) / dt);
    const Vector2 step = traj[k].pose.translation() - traj[k - 1].pose.translation();
    const double mid_yaw =
        traj[k - 1].pose.yaw() + 0.5 * core::WrapAngle(traj[k].pose.yaw() - traj[k - 1].pose.yaw());
    max_heading_error = std::max(
        max_heading_error, std::abs(core::WrapAngle(std::atan2(step.y(), step.x()) - mid_yaw)));
    EXPECT_NEAR(step.norm() / dt, 0.5 * (route->speed_mps[k] + route->speed_mps[k - 1]), 0.01);
  }
  // The planned turns reach 1 / min_turn_radius_m; path following adds its
  // own (about 0.005 1/m rms).
  EXPECT_LE(max_curvature, 1.0 / options.min_turn_radius_m + 0.05);
  EXPECT_LE(route->max_curvature_1pm, 1.0 / options.min_turn_radius_m + 0.05);
  EXPECT_GT(max_curvature, 0.1);  // it does turn
  EXPECT_LE(max_accel, options.max_accel_mps2 * 1.05);
  EXPECT_LE(max_yaw_accel, 3.0);
  EXPECT_LE(max_heading_error, 0.01);

  // A closed loop: the last sample is one step before the first.
  const double gap_m = (traj.front().pose.translation() - traj.back().pose.translation()).norm();
  EXPECT_LE(gap_m, options.max_speed_mps * dt + 1e-6);
  EXPECT_NEAR(core::WrapAngle(traj.front().pose.yaw() - traj.back().pose.yaw()), 0.0, 0.02);
  EXPECT_EQ(route->waypoints_m.front(), route->waypoints_m.back());
}

INSTANTIATE_TEST_SUITE_P(AllZones, RouteInZone,
                         ::testing::Combine(::testing::Values(Zone::kA, Zone::kB, Zone::kC,
                                                              Zone::kD),
                                            ::testing::Values(1u, 2u, 3u)),
                         [](const ::testing::TestParamInfo<RouteInZone::ParamType>& info) {
                           return std::string("Zone") +
                                  "ABCD"[static_cast<int>(std::get<0>(info.param))] + "Seed" +
                                  std::to_string(std::get<1>(info.param));
                         });

TEST(Route, ZoneBTraversesAislesEndToEnd) {
  const ZoneBOptions zone;
  const core::Result<World> world = BuildZoneB(zone);
  ASSERT_TRUE(world.ok());
  const core::Result<Route> route = GenerateRoute(*world, RouteOptions{});
  ASSERT_TRUE(route.ok()) << route.message();
  int aisle_traversals = 0;
  for (std::size_t i = 1; i < route->waypoints_m.size(); ++i) {
    const Vector2 d = route->waypoints_m[i] - route->waypoints_m[i - 1];
    if (std::abs(d.x()) < 1e-9 && std::abs(d.y()) > zone.aisle_length_m) ++aisle_traversals;
  }
  EXPECT_GE(aisle_traversals, 8);  // 1.2 km is mostly aisles of 89 m
}

TEST(Route, IsDeterministicForASeedAndDiffersAcrossSeeds) {
  const core::Result<World> world = BuildZone(Zone::kA, 1);
  ASSERT_TRUE(world.ok());
  RouteOptions options;
  options.length_m = 400.0;
  const core::Result<Route> a = GenerateRoute(*world, options);
  const core::Result<Route> b = GenerateRoute(*world, options);
  options.seed = 2;
  const core::Result<Route> c = GenerateRoute(*world, options);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(a->waypoints_m, b->waypoints_m);
  ASSERT_EQ(a->T_map_base.size(), b->T_map_base.size());
  EXPECT_TRUE(a->T_map_base.back().pose.IsApprox(b->T_map_base.back().pose, 0.0, 0.0));
  EXPECT_NE(a->waypoints_m, c->waypoints_m);
}

// A circle of radius R driven counter-clockwise, sampled every centimetre:
// the planned path whose deviation is easy to measure (radial offset).
std::vector<internal::PathSample> CircleLoop(double radius_m) {
  std::vector<internal::PathSample> loop;
  const double length_m = 2.0 * std::numbers::pi * radius_m;
  const int n = static_cast<int>(length_m / internal::kPathStepM);
  for (int i = 0; i <= n; ++i) {
    const double s = length_m * i / n;
    loop.push_back({s, radius_m * std::sin(s / radius_m), radius_m * (1.0 - std::cos(s / radius_m)),
                    s / radius_m, 1.0 / radius_m, 2.0});
  }
  return loop;
}

TEST(Route, TrackingDeviationIsASmoothSidewaysOffsetTheVehicleDrivesAlong) {
  constexpr double kRadiusM = 50.0;
  RouteOptions options;
  options.seed = 5;
  std::vector<internal::PathSample> loop = CircleLoop(kRadiusM);
  const std::vector<internal::PathSample> planned = loop;
  internal::AddTrackingDeviation(options, &loop);
  ASSERT_EQ(loop.size(), planned.size());

  // The offset (radial, inward positive = to the left of the motion) has the
  // requested spread and no more than a few of it; heading, curvature and arc
  // length are those of the driven curve.
  double sum2 = 0.0, max_abs = 0.0, traced_m = 0.0;
  double max_heading_error = 0.0, max_curvature_error = 0.0, max_heading_offset = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Vector2 centre(0.0, kRadiusM);
    const double d = kRadiusM - (Vector2(loop[i].x_m, loop[i].y_m) - centre).norm();
    sum2 += d * d;
    max_abs = std::max(max_abs, std::abs(d));
    max_heading_offset =
        std::max(max_heading_offset, std::abs(loop[i].yaw_rad - planned[i].yaw_rad));
    if (i == 0) continue;
    const double dx = loop[i].x_m - loop[i - 1].x_m, dy = loop[i].y_m - loop[i - 1].y_m;
    const double step_m = std::hypot(dx, dy);
    traced_m += step_m;
    const double mid_yaw = 0.5 * (loop[i].yaw_rad + loop[i - 1].yaw_rad);
    max_heading_error =
        std::max(max_heading_error, std::abs(core::WrapAngle(std::atan2(dy, dx) - mid_yaw)));
    const double numeric_curvature = (loop[i].yaw_rad - loop[i - 1].yaw_rad) / step_m;
    const double mean_curvature = 0.5 * (loop[i].curvature_1pm + loop[i - 1].curvature_1pm);
    max_curvature_error =
        std::max(max_curvature_error, std::abs(numeric_curvature - mean_curvature));
  }
  const double rms = std::sqrt(sum2 / static_cast<double>(loop.size()));
  EXPECT_NEAR(rms, options.tracking_deviation_m, 0.4 * options.tracking_deviation_m);
  EXPECT_LT(max_abs, 4.0 * options.tracking_deviation_m);
  EXPECT_GT(max_heading_offset, 1e-3);  // it does turn off the planned heading ..
  EXPECT_LT(max_heading_offset, 0.05);  // .. by a little
  EXPECT_LT(max_heading_error, 1e-5);
  EXPECT_LT(max_curvature_error, 1e-3);
  EXPECT_NEAR(loop.back().s_m, traced_m, 1e-6 * traced_m);
  // Still a loop: it ends where it starts, one turn round.
  EXPECT_NEAR(loop.back().x_m, loop.front().x_m, 1e-9);
  EXPECT_NEAR(loop.back().y_m, loop.front().y_m, 1e-9);
  EXPECT_NEAR(loop.back().yaw_rad - loop.front().yaw_rad, 2.0 * std::numbers::pi, 1e-9);

  // Off: the planned path exactly.
  options.tracking_deviation_m = 0.0;
  std::vector<internal::PathSample> exact = planned;
  internal::AddTrackingDeviation(options, &exact);
  for (std::size_t i = 0; i < exact.size(); i += 997) {
    EXPECT_EQ(exact[i].x_m, planned[i].x_m);
    EXPECT_EQ(exact[i].yaw_rad, planned[i].yaw_rad);
  }
}

TEST(Route, ReportsUnusableInputs) {
  EXPECT_FALSE(GenerateRoute(World{}, RouteOptions{}).ok());
  RouteOptions bad;
  bad.min_speed_mps = 2.5;
  const core::Result<Route> r = GenerateRoute(*BuildZone(Zone::kD, 1), bad);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("max_speed_mps"), std::string::npos) << r.message();
  // A wall across a corridor of zone D: the clearance check must refuse.
  World blocked = *BuildZone(Zone::kD, 1);
  for (double x : {20.0, 60.0, 120.0, 160.0}) {
    blocked.obstacles.push_back(
        {ObstacleKind::kPallet, OrientedBox::FromMinMax({x, 1.5}, {x + 1.0, 2.5}), 0.0, 1.0, 0.5});
    blocked.obstacles.push_back({ObstacleKind::kPallet,
                                 OrientedBox::FromMinMax({x, 31.5}, {x + 1.0, 32.5}), 0.0, 1.0,
                                 0.5});
  }
  const core::Result<Route> r2 = GenerateRoute(blocked, RouteOptions{});
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.message().find("min_clearance_m"), std::string::npos) << r2.message();
}

}  // namespace
}  // namespace groundline::sim
