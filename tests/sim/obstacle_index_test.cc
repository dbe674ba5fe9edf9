#include "groundline/sim/obstacle_index.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "groundline/sim/zones.h"

namespace groundline::sim {
namespace {

// Brute force over every edge of every obstacle, for reference.
double BruteForceRay(const World& world, const Vector2& origin, const Vector2& dir,
                     double max_range_m) {
  double best = std::numeric_limits<double>::infinity();
  for (const Obstacle& o : world.obstacles) {
    const auto c = o.box.Corners();
    for (int k = 0; k < 4; ++k) {
      best = std::min(best, IntersectRaySegment(origin, dir, c[k], c[(k + 1) % 4]));
    }
  }
  return best <= max_range_m ? best : std::numeric_limits<double>::infinity();
}

TEST(ObstacleIndex, RayCastsMatchBruteForceInZoneA) {
  const World world = *BuildZone(Zone::kA, 3);
  for (double cell : {0.25, 0.5, 2.0}) {
    const ObstacleIndex index(world, {cell, std::numeric_limits<double>::quiet_NaN()});
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> x(-5.0, 105.0), y(-5.0, 70.0), a(-M_PI, M_PI);
    for (int i = 0; i < 3000; ++i) {
      const double origin_y = y(rng);  // one draw per statement, last first
      const Vector2 origin(x(rng), origin_y);
      const double angle = i % 10 == 0 ? (i / 10 % 4) * M_PI / 2 : a(rng);  // axis-aligned too
      const Vector2 dir(std::cos(angle), std::sin(angle));
      const double expected = BruteForceRay(world, origin, dir, 30.0);
      const RayHit hit = index.CastRay(origin, dir, 30.0);
      if (std::isinf(expected)) {
        EXPECT_FALSE(hit.hit()) << i;
      } else {
        ASSERT_TRUE(hit.hit()) << i;
        EXPECT_NEAR(hit.range_m, expected, 1e-9) << i;
      }
    }
  }
}

TEST(ObstacleIndex, ClearanceIsTheDistanceToTheNearestObstacle) {
  World world;
  world.obstacles.push_back(
      {ObstacleKind::kWall, OrientedBox::FromMinMax({0, 0}, {40, 20}), 0.0, 5.0, 0.5});
  world.obstacles.push_back(
      {ObstacleKind::kPallet, OrientedBox::FromMinMax({50, 0}, {51, 1}), 0.0, 1.0, 0.5});
  const ObstacleIndex index(world, {});
  EXPECT_NEAR(index.ClearanceM({45, 0.5}, 10.0), 5.0, 1e-12);
  EXPECT_NEAR(index.ClearanceM({52, 2}, 10.0), std::sqrt(2.0), 1e-12);
  EXPECT_EQ(index.ClearanceM({20, 10}, 3.0), 0.0);  // deep inside the large box
  EXPECT_EQ(index.ClearanceM({80, 80}, 3.0), 3.0);  // nothing within the radius
}

TEST(ObstacleIndex, PlaneHeightSelectsObstacles) {
  World world;
  world.obstacles.push_back(
      {ObstacleKind::kRackBeam, OrientedBox::FromMinMax({0, 0}, {1, 1}), 1.5, 9.0, 0.5});
  world.obstacles.push_back(
      {ObstacleKind::kPallet, OrientedBox::FromMinMax({2, 0}, {3, 1}), 0.0, 1.0, 0.5});
  EXPECT_EQ(ObstacleIndex(world, {0.5, 0.18}).num_obstacles(), 1u);
  EXPECT_EQ(ObstacleIndex(world, {}).num_obstacles(), 2u);
  const RayHit hit = ObstacleIndex(world, {0.5, 0.18}).CastRay({-1, 0.5}, {1, 0}, 10.0);
  EXPECT_EQ(hit.obstacle, 1);
  EXPECT_NEAR(hit.range_m, 3.0, 1e-12);
  EXPECT_NEAR(hit.cos_incidence, 1.0, 1e-12);
}

}  // namespace
}  // namespace groundline::sim
