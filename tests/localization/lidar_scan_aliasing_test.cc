// DetectScanAliasing on hand-built worlds (lidar_test_world.h): a periodic
// rack aisle is aliased along the aisle; a lane along a wall
// with irregularly spaced pillars is not (the wall is consistent with every
// shift but carries no along-track evidence); the aisle stays aliased with
// its end wall 6.5-8.2 m ahead in range (one surface, capped); the aisle's
// junction with a cross aisle and an open hall are not aliased.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "groundline/localization/lidar/match_information.h"
#include "groundline/localization/lidar/scan_aliasing.h"
#include "lidar_test_world.h"

namespace groundline::localization::lidar {
namespace {

using testing::AddBox;
using testing::Segment;
using testing::SimulateScan;

using testing::AisleWorld;
using testing::kPitchM;

ScanAliasing Detect(const std::vector<Segment>& world, const core::SE2& pose,
                    const ScanAliasingOptions& options = {}) {
  const ScanPoints scan = SimulateScan(world, pose, 0.01, 3);
  const MatchInformation information =
      ComputeMatchInformation(scan.points, {0.05, 50.0, 0.01, 100.0});
  return DetectScanAliasing(scan, information, options);
}

TEST(ScanAliasing, PeriodicAisleIsAliasedAlongTheAisle) {
  const std::vector<Segment> aisle = AisleWorld(-54.0, 54.0);
  for (const double x : {0.3, 1.1, 2.0}) {
    const ScanAliasing a = Detect(aisle, core::SE2(x, 0.05, 0.02));
    EXPECT_TRUE(a.aliased) << x << ": score " << a.best_score;
    EXPECT_GT(std::abs(a.direction.x()), 0.98) << x;
    EXPECT_GT(a.best_score, 0.9) << x;
    EXPECT_GT(a.evidence, 1.0) << x;
  }
}

TEST(ScanAliasing, WallWithIrregularPillarsIsNotAliased) {
  // A lane 2 m from a long wall along x, 0.4 m pillars at irregular spacing
  // 3 m away on the other side. The old self-similarity score (the share of
  // all points that land on the scan after a shift) counted the wall.
  std::vector<Segment> world = {{{-40.0, -2.0}, {40.0, -2.0}}};
  for (const double x : {-17.0, -11.5, -8.2, -3.9, -1.1, 2.6, 4.1, 8.8, 12.0, 19.3}) {
    AddBox(&world, x, 3.0, x + 0.4, 3.4);
  }
  for (const double x : {0.0, 1.5, 3.0}) {
    const ScanAliasing a = Detect(world, core::SE2(x, 0.0, 0.0));
    EXPECT_FALSE(a.aliased) << x << ": score " << a.best_score;
    EXPECT_LT(a.best_score, 0.5) << x;
    EXPECT_GT(a.evidence, 5.0) << x;
  }
}

TEST(ScanAliasing, AisleWithItsFarEndInRangeIsAliased) {
  // The racks end 8 m ahead, a cross wall behind them 6.5-8.2 m from the
  // robot, within the 30 m range (an aisle keyframe of zone_regions.h: more
  // than 5 m from the end). A pose a bay further would see the wall a bay
  // closer, where this scan sees free space. But the wall is one surface
  // against the many uprights and pallet sides that agree with the shift, so
  // the aisle is still aliased; uncapped, the wall's hundred returns would
  // outvote them.
  std::vector<Segment> aisle = AisleWorld(-54.0, 8.0 - 1e-3);
  aisle.push_back({{8.5, -2.4}, {8.5, 2.4}});
  for (const double x : {0.3, 1.1, 2.0}) {
    const ScanAliasing a = Detect(aisle, core::SE2(x, 0.05, 0.0));
    EXPECT_TRUE(a.aliased) << x << ": score " << a.best_score;
    EXPECT_GT(std::abs(a.direction.x()), 0.98) << x;
    ScanAliasingOptions uncapped;
    uncapped.max_surface_points = 1e6;
    const ScanAliasing b = Detect(aisle, core::SE2(x, 0.05, 0.0), uncapped);
    EXPECT_FALSE(b.aliased) << x << ": uncapped score " << b.best_score;
  }
}

TEST(ScanAliasing, JunctionOfTheAisleWithACrossAisleIsNotAliased) {
  // A 4 m cross aisle cuts the rack rows at x in [-2, 2]: from the crossing
  // the four rack ends are distinct surfaces around the robot.
  std::vector<Segment> world = AisleWorld(-54.0, -2.0);
  for (const Segment& s : AisleWorld(2.0, 54.0)) world.push_back(s);
  for (const double x : {-0.5, 0.0, 0.6}) {
    const ScanAliasing a = Detect(world, core::SE2(x, 0.05, 0.1));
    EXPECT_FALSE(a.aliased) << x << ": score " << a.best_score;
    EXPECT_LT(a.best_score, 0.5) << x;
  }
}

TEST(ScanAliasing, OpenHallWithScatteredLoadsIsNotAliased) {
  // A 30 m x 20 m hall with pallet loads standing at irregular places.
  std::vector<Segment> hall;
  AddBox(&hall, -15.0, -10.0, 15.0, 10.0);
  const double loads[][2] = {{3.1, 2.2},  {-4.7, 5.3}, {7.9, -3.6},  {-8.2, -6.1},
                             {1.3, -7.4}, {10.5, 6.8}, {-11.0, 1.7}, {5.6, 4.9}};
  for (const auto& c : loads) AddBox(&hall, c[0], c[1], c[0] + 1.2, c[1] + 1.0);
  for (const core::SE2& pose :
       {core::SE2(0.5, 0.3, 0.2), core::SE2(-3.0, -2.0, 1.4), core::SE2(6.0, 0.5, -2.5)}) {
    const ScanAliasing a = Detect(hall, pose);
    EXPECT_FALSE(a.aliased) << pose.translation().transpose() << ": score " << a.best_score;
    EXPECT_LT(a.best_score, 0.5) << pose.translation().transpose();
  }
}

TEST(ScanAliasing, FewPointsAreNotChecked) {
  ScanPoints scan;
  for (int i = 0; i < 5; ++i)
    scan.points.push_back({core::Vector2(1.0, 0.2 * i), core::Vector2::UnitX()});
  const ScanAliasing a = DetectScanAliasing(scan, ComputeMatchInformation(scan.points, {}), {});
  EXPECT_FALSE(a.aliased);
}

}  // namespace
}  // namespace groundline::localization::lidar
