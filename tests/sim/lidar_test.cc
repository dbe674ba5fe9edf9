#include "groundline/sim/lidar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "groundline/sim/zones.h"
#include "test_units.h"

namespace groundline::sim {
namespace {

using ::groundline::testing::kDeg;

// Float ranges: relative precision 2^-24, plus the double arithmetic upstream.
double FloatTolerance(double range_m) { return 2e-7 * range_m + 1e-6; }

LidarOptions NoiseFree() {
  LidarOptions options;
  options.range_noise_sigma_m = 0.0;
  options.dropout_probability = 0.0;
  return options;
}

World OneWall(const OrientedBox& box) {
  World world;
  world.name = "one_wall";
  world.obstacles.push_back({ObstacleKind::kWall, box, 0.0, 5.0, 0.5});
  return world;
}

TEST(PlanarLidar, RayCountAndAnglesFollowTheOptions) {
  const LidarOptions options;
  const PlanarLidar lidar(World{}, options);
  const LaserScan scan = lidar.Scan(core::SE2(), 0.0, 0);
  EXPECT_EQ(options.NumRays(), 819);  // floor(270 / 0.33) + 1
  ASSERT_EQ(scan.ranges_m.size(), 819u);
  ASSERT_EQ(scan.intensities.size(), 819u);
  EXPECT_NEAR(scan.angle_increment_rad, 0.33 * kDeg, 1e-12);
  EXPECT_NEAR(scan.angle_min_rad, -409 * 0.33 * kDeg, 1e-12);  // symmetric, within +-135 deg
  EXPECT_NEAR(scan.AngleRad(818), -scan.angle_min_rad, 1e-12);
  EXPECT_NEAR(scan.AngleRad(409), 0.0, 1e-15);
  EXPECT_GE(scan.angle_min_rad, -135.0 * kDeg);
  EXPECT_LT(scan.angle_min_rad - scan.angle_increment_rad, -135.0 * kDeg);
  EXPECT_EQ(scan.range_max_m, 25.0);

  LidarOptions half;
  half.field_of_view_rad = 180.0 * kDeg;
  half.angular_resolution_rad = 1.0 * kDeg;
  EXPECT_EQ(half.NumRays(), 181);
  EXPECT_EQ(PlanarLidar(World{}, half).Scan(core::SE2(), 0.0, 0).ranges_m.size(), 181u);
}

TEST(PlanarLidar, EmptyWorldGivesNoReturnEverywhere) {
  const PlanarLidar lidar(World{}, NoiseFree());
  const LaserScan scan = lidar.Scan(core::SE2(3.0, 4.0, 1.0), 0.0, 0);
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    EXPECT_TRUE(std::isinf(scan.ranges_m[i]) && scan.ranges_m[i] > 0) << i;
    EXPECT_EQ(scan.intensities[i], 0.0f);
  }
}

// A wall whose face is the line x = 6 in the map; the vehicle is at (1, 0.5)
// and turned by yaw, so rays reach the wall at all incidences, and those
// longer than 25 m must come back as no-return.
TEST(PlanarLidar, RangesEqualTheAnalyticDistanceToAWall) {
  const World world = OneWall(OrientedBox::FromMinMax({6.0, -100.0}, {6.3, 100.0}));
  const LidarOptions options = NoiseFree();
  const PlanarLidar lidar(world, options);
  for (double yaw : {0.0, 0.4, -1.1}) {
    const core::SE2 T_map_base(1.0, 0.5, yaw);
    const LaserScan scan = lidar.Scan(T_map_base, 0.0, 0);
    const core::SE2 T_map_lidar = T_map_base * options.T_base_lidar;
    int hits = 0, misses = 0;
    for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
      const double angle = T_map_lidar.yaw() + scan.AngleRad(i);
      const double c = std::cos(angle);
      const double expected =
          c > 0.0 ? (6.0 - T_map_lidar.x()) / c : std::numeric_limits<double>::infinity();
      if (expected <= options.range_max_m) {
        ++hits;
        EXPECT_NEAR(scan.ranges_m[i], expected, FloatTolerance(expected)) << yaw << " " << i;
        EXPECT_NEAR(scan.intensities[i], 0.5 * std::abs(c), 1e-6);
      } else {
        ++misses;
        EXPECT_TRUE(std::isinf(scan.ranges_m[i]) && scan.ranges_m[i] > 0) << yaw << " " << i;
      }
    }
    EXPECT_GT(hits, 100);
    EXPECT_GT(misses, 100);
  }
}

TEST(PlanarLidar, RangesEqualTheAnalyticDistanceToAnObliqueWall) {
  // Face through (8, 0) with normal n at 30 deg (thickness 0.2 centred 0.1 behind).
  const double a = 30.0 * kDeg;
  const Vector2 n(std::cos(a), std::sin(a));
  const Vector2 t(-n.y(), n.x());
  const Vector2 center = Vector2(8.0, 0.0) + 0.1 * n;
  const World world =
      OneWall(OrientedBox::AlongSegment(center - 200.0 * t, center + 200.0 * t, 0.2));
  const LidarOptions options = NoiseFree();
  const PlanarLidar lidar(world, options);
  const core::SE2 T_map_base(-2.0, 1.0, 0.2);
  const core::SE2 T_map_lidar = T_map_base * options.T_base_lidar;
  const LaserScan scan = lidar.Scan(T_map_base, 0.0, 0);
  int hits = 0;
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double angle = T_map_lidar.yaw() + scan.AngleRad(i);
    const Vector2 dir(std::cos(angle), std::sin(angle));
    const double along = n.dot(dir);
    const double expected = along > 0.0
                                ? n.dot(Vector2(8.0, 0.0) - T_map_lidar.translation()) / along
                                : std::numeric_limits<double>::infinity();
    if (expected <= options.range_max_m) {
      ++hits;
      EXPECT_NEAR(scan.ranges_m[i], expected, FloatTolerance(expected)) << i;
    } else {
      EXPECT_TRUE(std::isinf(scan.ranges_m[i]) && scan.ranges_m[i] > 0) << i;
    }
  }
  EXPECT_GT(hits, 300);
}

TEST(PlanarLidar, SeesOnlyObstaclesCrossingTheScanPlane) {
  World world;
  world.obstacles.push_back(
      {ObstacleKind::kRackBeam, OrientedBox::FromMinMax({3, -5}, {3.1, 5}), 1.5, 9.5, 0.3});
  world.obstacles.push_back(
      {ObstacleKind::kPallet, OrientedBox::FromMinMax({7, -5}, {8, 5}), 0.0, 1.35, 0.6});
  const LidarOptions options = NoiseFree();
  const LaserScan scan = PlanarLidar(world, options).Scan(core::SE2(), 0.0, 0);
  const std::size_t ahead = 409;  // angle 0
  EXPECT_NEAR(scan.AngleRad(ahead), 0.0, 1e-9);
  EXPECT_NEAR(scan.ranges_m[ahead], 7.0 - 0.84, FloatTolerance(7.0));
}

TEST(PlanarLidar, CloserThanRangeMinIsNegativeInfinity) {
  const World world = OneWall(OrientedBox::FromMinMax({0.86, -1.0}, {1.0, 1.0}));
  const LaserScan scan = PlanarLidar(world, NoiseFree()).Scan(core::SE2(), 0.0, 0);
  EXPECT_TRUE(std::isinf(scan.ranges_m[409]) && scan.ranges_m[409] < 0);
}

TEST(PlanarLidar, MovingObstacleAppearsAtTheRightRangeAtTheRightTime) {
  MovingObstacle walker;
  walker.kind = MovingKind::kPedestrian;
  walker.radius_m = 0.2;
  walker.path_m = {{10.0, -5.0}, {10.0, 5.0}};
  walker.speed_mps = 1.0;
  MovingObstacle forklift;
  forklift.half_extent_m = {1.0, 0.5};
  forklift.path_m = {{-20.0, 6.0}, {20.0, 6.0}};
  forklift.speed_mps = 2.0;
  World world;
  world.moving = {walker, forklift};
  // The LiDAR at the map origin, looking along +x.
  const LidarOptions options = NoiseFree();
  const core::SE2 T_map_base = options.T_base_lidar.Inverse();
  const PlanarLidar lidar(world, options);
  const std::size_t ahead = 409;

  // t = 5 s: the walker crosses y = 0, 9.8 m ahead; t = 0 s and 12 s: away.
  EXPECT_NEAR(lidar.Scan(T_map_base, 5.0, 0).ranges_m[ahead], 9.8, FloatTolerance(9.8));
  EXPECT_TRUE(std::isinf(lidar.Scan(T_map_base, 0.0, 0).ranges_m[ahead]));
  // Ping-pong: back at y = 0 at t = 15 s, facing -y.
  EXPECT_NEAR(lidar.Scan(T_map_base, 15.0, 0).ranges_m[ahead], 9.8, FloatTolerance(9.8));
  EXPECT_NEAR(world.moving[0].PoseAt(15.0).yaw(), -std::numbers::pi / 2.0, 1e-12);

  // The forklift's centre is at x = 0 at t = 10 s; its near side is y = 5.5.
  const LaserScan scan = lidar.Scan(T_map_base, 10.0, 0);
  const std::size_t left = 409 + static_cast<std::size_t>(std::lround(90.0 / 0.33));
  const double expected = 5.5 / std::sin(scan.AngleRad(left));
  EXPECT_NEAR(scan.ranges_m[left], expected, FloatTolerance(expected));
  EXPECT_TRUE(std::isinf(lidar.Scan(T_map_base, 0.0, 0).ranges_m[left]));
}

TEST(PlanarLidar, NoiseAndDropoutsHaveTheConfiguredStatisticsAndAreReproducible) {
  const World world = OneWall(OrientedBox::FromMinMax({6.0, -100.0}, {6.3, 100.0}));
  LidarOptions options;
  options.range_noise_sigma_m = 0.02;
  options.dropout_probability = 0.1;
  const PlanarLidar lidar(world, options);
  const LidarOptions exact_options = NoiseFree();
  const LaserScan exact = PlanarLidar(world, exact_options).Scan(core::SE2(), 0.0, 0);
  double sum = 0.0, sum2 = 0.0;
  int count = 0, dropped = 0, total = 0;
  for (std::uint64_t k = 0; k < 50; ++k) {
    const LaserScan scan = lidar.Scan(core::SE2(), 0.0, k);
    for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
      if (!std::isfinite(exact.ranges_m[i])) continue;
      ++total;
      if (std::isinf(scan.ranges_m[i])) {
        ++dropped;
        continue;
      }
      const double e = scan.ranges_m[i] - exact.ranges_m[i];
      sum += e;
      sum2 += e * e;
      ++count;
    }
  }
  const double mean = sum / count;
  const double sigma = std::sqrt(sum2 / count - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.002);
  EXPECT_NEAR(sigma, 0.02, 0.002);
  EXPECT_NEAR(static_cast<double>(dropped) / total, 0.1, 0.01);

  const LaserScan a = lidar.Scan(core::SE2(), 0.0, 7);
  const LaserScan b = lidar.Scan(core::SE2(), 0.0, 7);
  const LaserScan c = lidar.Scan(core::SE2(), 0.0, 8);
  EXPECT_EQ(a.ranges_m, b.ranges_m);
  EXPECT_NE(a.ranges_m, c.ranges_m);
}

TEST(PlanarLidar, ScanAlongCastsEachRayFromThePoseAtItsOwnTime) {
  const World world = OneWall(OrientedBox::FromMinMax({20.0, -100.0}, {20.3, 100.0}));
  const LidarOptions options = NoiseFree();
  const PlanarLidar lidar(world, options);
  core::Trajectory trajectory;
  for (int k = 0; k <= 100; ++k) {
    trajectory.push_back({0.01 * k, core::SE2(2.0 * 0.01 * k, 0.0, 0.0), std::nullopt});
  }
  const LaserScan scan = lidar.ScanAlong(trajectory, 0.2, 0);
  for (std::size_t i : {std::size_t{300}, std::size_t{409}, std::size_t{520}}) {
    const double t = 0.2 + static_cast<double>(i) * options.TimeIncrementS();
    const double expected = (20.0 - 0.84 - 2.0 * t) / std::cos(scan.AngleRad(i));
    EXPECT_NEAR(scan.ranges_m[i], expected, FloatTolerance(expected)) << i;
  }
  EXPECT_EQ(SimulateScans(lidar, trajectory).size(), 16u);  // t = 0, 1/15, ..., 1
}

// Zone B with every bay full is periodic along an aisle with the upright pitch:
// the scans one pitch apart are identical, half a pitch apart they are not.
TEST(PlanarLidar, ZoneBAisleIsPeriodicAlongItsAxis) {
  ZoneBOptions zone;
  zone.num_aisles = 3;
  zone.num_pedestrians = 0;
  const core::Result<World> world = BuildZoneB(zone);
  ASSERT_TRUE(world.ok()) << world.message();
  const PlanarLidar lidar(*world, NoiseFree());
  const double x = zone.AisleCenterXM(1);
  const double y = zone.RackStartYM() + 30.0;
  const LaserScan a = lidar.Scan(core::SE2(x, y, std::numbers::pi / 2), 0.0, 0);
  const LaserScan b =
      lidar.Scan(core::SE2(x, y + zone.upright_pitch_m, std::numbers::pi / 2), 0.0, 0);
  const LaserScan c =
      lidar.Scan(core::SE2(x, y + 0.5 * zone.upright_pitch_m, std::numbers::pi / 2), 0.0, 0);
  int differ_ab = 0, differ_ac = 0, finite = 0;
  for (std::size_t i = 0; i < a.ranges_m.size(); ++i) {
    finite += std::isfinite(a.ranges_m[i]) ? 1 : 0;
    differ_ab += std::abs(a.ranges_m[i] - b.ranges_m[i]) > 1e-4 ? 1 : 0;
    differ_ac += std::abs(a.ranges_m[i] - c.ranges_m[i]) > 1e-4 ? 1 : 0;
  }
  EXPECT_GT(finite, 700);
  EXPECT_EQ(differ_ab, 0);
  EXPECT_GT(differ_ac, 100);
}

}  // namespace
}  // namespace groundline::sim
