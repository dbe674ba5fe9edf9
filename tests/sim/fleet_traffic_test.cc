// Fleet traffic: a robot that yields keeps its path and its distance from
// the robots before it, stops and starts like a vehicle, and is not touched
// where nothing is in its way; a start where another robot stands is an
// error.
#include "groundline/sim/fleet_traffic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace groundline::sim {
namespace {

constexpr double kHalfPi = std::numbers::pi / 2.0;

// A straight route from `start` along its heading: from rest up to
// cruise_mps at accel_mps2, on, and back to rest at its end; 100 Hz.
Route StraightRoute(const core::SE2& start, double length_m, double cruise_mps, double accel_mps2) {
  Route route;
  const double dt = 0.01;
  double s = 0.0, v = 0.0;
  for (int i = 0;; ++i) {
    route.T_map_base.push_back({i * dt, start * core::SE2(s, 0.0, 0.0), std::nullopt});
    route.speed_mps.push_back(v);
    route.yaw_rate_radps.push_back(0.0);
    if (s >= length_m) break;
    const double to_go = length_m - s;
    const double braking = std::sqrt(2.0 * accel_mps2 * to_go);
    v = std::min({cruise_mps, v + accel_mps2 * dt, braking});
    v = std::max(v, 0.01);
    s = std::min(length_m, s + v * dt);
  }
  route.length_m = length_m;
  route.duration_s = route.T_map_base.back().stamp_s;
  return route;
}

TEST(FleetTraffic, ARobotCrossingAnotherWaitsAndKeepsItsPathAndDistance) {
  // Robot 0 drives along y = 0 from x = -20 to 20; robot 1's route crosses
  // it at the origin going north, planned to be there at the same time.
  const Route first = StraightRoute(core::SE2(-20.0, 0.0, 0.0), 40.0, 1.5, 0.5);
  const Route planned = StraightRoute(core::SE2(0.0, -20.0, kHalfPi), 40.0, 1.5, 0.5);
  const TrafficOptions options;
  ASSERT_LT(MinimumSeparation(planned.T_map_base, first.T_map_base).distance_m, 0.5);

  const core::Result<Route> yielded = YieldToOthers(planned, {&first.T_map_base}, options);
  ASSERT_TRUE(yielded.ok()) << yielded.message();
  const Separation closest = MinimumSeparation(yielded->T_map_base, first.T_map_base);
  EXPECT_GE(closest.distance_m, 0.95 * options.separation_m) << "at " << closest.stamp_s << " s";
  // The same path: every pose on x = 0 heading north, never backwards, to the same end.
  double y = -21.0;
  for (const core::StampedPose& p : yielded->T_map_base) {
    EXPECT_NEAR(p.pose.x(), 0.0, 1e-9);
    EXPECT_NEAR(p.pose.yaw(), kHalfPi, 1e-9);
    EXPECT_GE(p.pose.y(), y - 1e-12);
    y = p.pose.y();
  }
  EXPECT_NEAR(yielded->T_map_base.back().pose.y(), 20.0, 1e-9);
  // It waited: later than planned, and stopped on the way.
  EXPECT_GT(yielded->duration_s, planned.duration_s + 2.0);
  const std::vector<double>& v = yielded->speed_mps;
  const bool stopped =
      std::any_of(v.begin() + 100, v.end() - 100, [](double s) { return s < 1e-6; });
  EXPECT_TRUE(stopped);
  // Like a vehicle: speeds from the poses match speed_mps; braking and
  // speeding up within twice the braking limit over any half second, and no
  // step in speed beyond a creeping 4 cm/s (the last centimetres of a stop).
  const auto& T = yielded->T_map_base;
  for (std::size_t i = 1; i < T.size(); ++i) {
    const double dt = T[i].stamp_s - T[i - 1].stamp_s;
    EXPECT_NEAR(dt, 0.01, 1e-9);
    const double moved = (T[i].pose.translation() - T[i - 1].pose.translation()).norm();
    EXPECT_NEAR(moved / dt, v[i - 1], 0.05) << "at " << T[i].stamp_s << " s";
    EXPECT_LE(std::abs(v[i] - v[i - 1]), 0.04) << "at " << T[i].stamp_s << " s";
    if (i >= 50) {
      EXPECT_LE(std::abs(v[i] - v[i - 50]) / 0.5, 2.0 * options.max_brake_mps2 + 0.1)
          << "at " << T[i].stamp_s << " s";
    }
  }
}

TEST(FleetTraffic, ARouteWithNothingInItsWayIsNotChanged) {
  const Route first = StraightRoute(core::SE2(-20.0, 30.0, 0.0), 40.0, 1.5, 0.5);
  const Route planned = StraightRoute(core::SE2(0.0, -20.0, kHalfPi), 20.0, 1.5, 0.5);
  const core::Result<Route> yielded = YieldToOthers(planned, {&first.T_map_base}, {});
  ASSERT_TRUE(yielded.ok()) << yielded.message();
  ASSERT_EQ(yielded->T_map_base.size(), planned.T_map_base.size());
  for (std::size_t i = 0; i < planned.T_map_base.size(); ++i) {
    EXPECT_NEAR(yielded->T_map_base[i].stamp_s, planned.T_map_base[i].stamp_s, 1e-9);
    EXPECT_LT((yielded->T_map_base[i].pose.translation() - planned.T_map_base[i].pose.translation())
                  .norm(),
              1e-9);
  }
}

TEST(FleetTraffic, AStartWhereAnotherRobotStandsIsAnError) {
  const Route first = StraightRoute(core::SE2(5.0, -1.0, 0.0), 40.0, 1.5, 0.5);
  const Route planned = StraightRoute(core::SE2(5.0, 0.5, kHalfPi), 10.0, 1.5, 0.5);
  const core::Result<Route> yielded = YieldToOthers(planned, {&first.T_map_base}, {});
  ASSERT_FALSE(yielded.ok());
  EXPECT_NE(yielded.message().find("start"), std::string::npos) << yielded.message();
}

}  // namespace
}  // namespace groundline::sim
