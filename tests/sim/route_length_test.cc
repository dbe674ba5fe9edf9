// Route lengths: an open route has exactly the requested length in every zone,
// whatever the road graph's edge lengths; a closed loop returns to its start.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>

#include "groundline/sim/route.h"
#include "groundline/sim/zones.h"

namespace groundline::sim {
namespace {

double TracedLengthM(const core::Trajectory& traj) {
  double traced_m = 0.0;
  for (std::size_t k = 1; k < traj.size(); ++k) {
    traced_m += (traj[k].pose.translation() - traj[k - 1].pose.translation()).norm();
  }
  return traced_m;
}

class OpenRouteLength : public ::testing::TestWithParam<std::tuple<Zone, double>> {};

TEST_P(OpenRouteLength, IsTheRequestedLengthFromRestToRest) {
  const auto [zone, length_m] = GetParam();
  const core::Result<World> world = BuildZone(zone, 7);
  ASSERT_TRUE(world.ok()) << world.message();
  RouteOptions options;
  options.seed = 7;
  options.length_m = length_m;
  const core::Result<Route> route = GenerateRoute(*world, options);
  ASSERT_TRUE(route.ok()) << route.message();
  EXPECT_FALSE(route->closed_loop);
  EXPECT_NEAR(route->length_m, length_m, 1e-9 * length_m);
  // The samples trace it (the last one is the end of the route).
  EXPECT_NEAR(TracedLengthM(route->T_map_base), length_m, 1e-3 * length_m);
  EXPECT_NEAR(route->T_map_base.back().stamp_s, route->duration_s, 1.0 / options.sample_rate_hz);
  // From rest to rest, never above the speed limit, within the acceleration limit.
  EXPECT_EQ(route->speed_mps.front(), 0.0);
  EXPECT_LT(route->speed_mps.back(), 0.05);
  const double dt = 1.0 / options.sample_rate_hz;
  for (std::size_t k = 1; k < route->speed_mps.size(); ++k) {
    ASSERT_LE(route->speed_mps[k], options.max_speed_mps + 1e-9);
    ASSERT_LE(std::abs(route->speed_mps[k] - route->speed_mps[k - 1]) / dt,
              1.05 * options.max_accel_mps2 + 1e-6)
        << "at sample " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(AllZones, OpenRouteLength,
                         ::testing::Combine(::testing::Values(Zone::kA, Zone::kB, Zone::kC,
                                                              Zone::kD),
                                            ::testing::Values(50.0, 333.0, 900.0)),
                         [](const ::testing::TestParamInfo<OpenRouteLength::ParamType>& info) {
                           return std::string("Zone") +
                                  "ABCD"[static_cast<int>(std::get<0>(info.param))] +
                                  std::to_string(static_cast<int>(std::get<1>(info.param))) + "m";
                         });

// Zone D's shortest corridor loop is ~250 m: 600 m is more than two laps.
TEST(OpenRoute, DrivesLapAfterLapWhenTheLoopIsShorter) {
  const core::Result<World> world = BuildZone(Zone::kD, 1);
  ASSERT_TRUE(world.ok());
  RouteOptions options;
  options.length_m = 600.0;
  const core::Result<Route> route = GenerateRoute(*world, options);
  ASSERT_TRUE(route.ok()) << route.message();
  EXPECT_NEAR(TracedLengthM(route->T_map_base), 600.0, 0.6);
}

class ClosedLoopLength : public ::testing::TestWithParam<std::tuple<Zone, double>> {};

TEST_P(ClosedLoopLength, ReturnsToItsStartWithinTheTolerance) {
  const auto [zone, length_m] = GetParam();
  const core::Result<World> world = BuildZone(zone, 3);
  ASSERT_TRUE(world.ok()) << world.message();
  RouteOptions options;
  options.seed = 3;
  options.length_m = length_m;
  options.closed_loop = true;
  const core::Result<Route> route = GenerateRoute(*world, options);
  ASSERT_TRUE(route.ok()) << route.message();
  EXPECT_TRUE(route->closed_loop);
  EXPECT_NEAR(route->length_m, length_m, options.length_tolerance_fraction * length_m);
  const core::Trajectory& traj = route->T_map_base;
  const double dt = 1.0 / options.sample_rate_hz;
  // The loop closes within one more sample's travel at speed.
  const double gap_m = (traj.front().pose.translation() - traj.back().pose.translation()).norm();
  EXPECT_LE(gap_m, route->speed_mps.back() * dt + 1e-3);
  EXPECT_GT(route->speed_mps.front(), options.min_speed_mps - 1e-9);
  EXPECT_NEAR(core::WrapAngle(traj.front().pose.yaw() - traj.back().pose.yaw()), 0.0, 0.02);
  EXPECT_NEAR(TracedLengthM(traj) + gap_m, route->length_m, 1e-3 * route->length_m);
}

INSTANTIATE_TEST_SUITE_P(Zones, ClosedLoopLength,
                         ::testing::Values(std::tuple(Zone::kA, 800.0),
                                           std::tuple(Zone::kB, 1200.0),
                                           std::tuple(Zone::kC, 600.0),
                                           std::tuple(Zone::kD, 1206.0)),
                         [](const ::testing::TestParamInfo<ClosedLoopLength::ParamType>& info) {
                           return std::string("Zone") +
                                  "ABCD"[static_cast<int>(std::get<0>(info.param))] +
                                  std::to_string(static_cast<int>(std::get<1>(info.param))) + "m";
                         });

TEST(ClosedLoop, OutOfReachLengthNamesTheWayOut) {
  const core::Result<World> world = BuildZone(Zone::kD, 1);
  ASSERT_TRUE(world.ok());
  RouteOptions options;
  options.length_m = 100.0;  // shorter than any loop of the corridors
  options.closed_loop = true;
  const core::Result<Route> route = GenerateRoute(*world, options);
  ASSERT_FALSE(route.ok());
  EXPECT_NE(route.message().find("closed_loop: false"), std::string::npos) << route.message();
}

}  // namespace
}  // namespace groundline::sim
