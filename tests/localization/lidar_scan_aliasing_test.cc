// DetectScanAliasing on hand-built worlds (lidar_test_world.h): a periodic
// rack aisle is aliased along the aisle; a lane along a wall
// with irregularly spaced pillars is not (the wall is consistent with every
// shift but carries no along-track evidence); the same aisle with its end
// wall in view is not (the end contradicts the shift).
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

constexpr double kPitchM = 2.7;

// A 2.2 m wide aisle along x over [x0, x1]: uprights (0.1 m x 0.08 m) every
// kPitchM on both faces (y = +-1.1) and two 1.0 m pallet loads per bay set
// back 5 cm, a wall behind each rack.
std::vector<Segment> AisleWorld(double x0, double x1) {
  std::vector<Segment> walls;
  for (double x = x0; x + kPitchM <= x1 + 1e-9; x += kPitchM) {
    for (double side : {-1.0, 1.0}) {
      const double face = 1.1 * side, depth = 1.1 * side;
      AddBox(&walls, x, std::min(face, face + 0.08 * side), x + 0.1,
             std::max(face, face + 0.08 * side));
      for (double offset : {0.25, 1.45}) {
        const double y0 = face + 0.05 * side, y1 = face + depth;
        AddBox(&walls, x + offset, std::min(y0, y1), x + offset + 1.0, std::max(y0, y1));
      }
    }
  }
  walls.push_back({{x0, -2.4}, {x1, -2.4}});
  walls.push_back({{x0, 2.4}, {x1, 2.4}});
  return walls;
}

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

TEST(ScanAliasing, AisleWithItsEndInViewIsNotAliased) {
  // The aisle ends 6 m ahead in a cross wall: a pose a bay further would see
  // the wall a bay closer, where this scan sees free space.
  std::vector<Segment> aisle = AisleWorld(-54.0, 6.0 - 1e-3);
  aisle.push_back({{6.5, -2.4}, {6.5, 2.4}});
  const ScanAliasing a = Detect(aisle, core::SE2(0.3, 0.05, 0.0));
  EXPECT_FALSE(a.aliased) << "score " << a.best_score;
  // The same place far from the end is aliased (the end is the difference).
  const ScanAliasing deep = Detect(AisleWorld(-54.0, 54.0), core::SE2(0.3, 0.05, 0.0));
  EXPECT_TRUE(deep.aliased) << "score " << deep.best_score;
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
