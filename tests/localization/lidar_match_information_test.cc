// The Fisher information of a scan match: rank 2 with the null direction
// along the aisle in a corridor, rank 3 in a room; and the grid's log-odds
// and its compression.
#include "groundline/localization/lidar/match_information.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "groundline/localization/lidar/probability_grid.h"
#include "lidar_test_world.h"
#include "test_units.h"

namespace groundline::localization::lidar {
namespace {

using ::groundline::testing::kDeg;

TEST(LidarMatchInformation, CorridorIsRankTwoWithNullDirectionAlongTheAisle) {
  for (double yaw_deg : {0.0, 30.0, -75.0}) {
    const core::SE2 T(2.0, 0.3, yaw_deg * kDeg);
    const ScanPoints scan = testing::SimulateScan(testing::CorridorWorld(), T, 0.005, 3);
    const MatchInformation info = ComputeMatchInformation(scan.points, {});
    EXPECT_EQ(info.rank, 2) << yaw_deg;
    EXPECT_TRUE(info.degenerate);
    // The aisle (world x) seen from the base: rotated by -yaw; no rotation part.
    const core::Vector2 aisle_base(std::cos(-yaw_deg * kDeg), std::sin(-yaw_deg * kDeg));
    const core::Vector3& d = info.weakest_direction;
    const double angle =
        std::acos(std::min(1.0, std::abs(d.head<2>().normalized().dot(aisle_base))));
    EXPECT_LT(angle, 3.0 * kDeg) << yaw_deg;
    EXPECT_LT(std::abs(d(2)), 0.05);
    // The kept square root carries (almost) nothing along the aisle.
    const core::Vector3 along(aisle_base.x(), aisle_base.y(), 0.0);
    EXPECT_LT((info.sqrt_information * along).norm(), 1e-3 * info.sqrt_information.norm());
    EXPECT_TRUE((info.sqrt_information.transpose() * info.sqrt_information)
                    .isApprox(info.sqrt_information.transpose() * info.sqrt_information));
  }
}

TEST(LidarMatchInformation, RoomIsRankThree) {
  const ScanPoints scan = testing::SimulateScan(testing::RoomWorld(), {0.5, -0.5, 0.4}, 0.005, 4);
  const MatchInformation info = ComputeMatchInformation(scan.points, {});
  EXPECT_EQ(info.rank, 3);
  EXPECT_FALSE(info.degenerate);
  EXPECT_GT(info.scaled_eigenvalues(0), 0.1 * info.scaled_eigenvalues(2));
  // Full rank: S^T S reproduces the information.
  EXPECT_TRUE(
      (info.sqrt_information.transpose() * info.sqrt_information).isApprox(info.information, 1e-9));
}

TEST(LidarProbabilityGrid, HitsMissesClampingAndGrowth) {
  ProbabilityGridOptions options;
  ProbabilityGrid grid(options, core::Vector2(0.0, 0.0), 8, 8);
  const core::Vector2 origin(0.12, 0.12), wall(2.02, 0.12);
  grid.InsertScan(origin, {wall});
  EXPECT_GT(grid.width(), 40);  // grew to reach x = 2 m
  EXPECT_NEAR(grid.Probability(grid.CellOf(wall)), options.hit_probability, 1e-6);
  const CellIndex between = grid.CellOf({1.0, 0.12});
  EXPECT_NEAR(grid.Probability(between), options.miss_probability, 1e-6);
  EXPECT_FALSE(grid.IsKnown(grid.CellOf({1.0, 1.0})));
  EXPECT_NEAR(grid.Probability(grid.CellOf({1.0, 1.0})), options.min_probability, 1e-6);
  for (int i = 0; i < 200; ++i) grid.InsertScan(origin, {wall});
  EXPECT_NEAR(grid.Probability(grid.CellOf(wall)), options.max_probability, 1e-5);
  EXPECT_NEAR(grid.Probability(between), options.min_probability, 1e-5);
  // A cell hit and crossed in one scan counts as hit once.
  ProbabilityGrid once(options, core::Vector2(0.0, 0.0), 64, 64);
  once.InsertScan(origin, {core::Vector2(1.0, 0.12), core::Vector2(2.0, 0.12)});
  EXPECT_NEAR(once.Probability(once.CellOf({1.0, 0.12})), options.hit_probability, 1e-6);
  const core::Vector2 corner = grid.origin_m();
  grid.CropToKnown();
  EXPECT_LE(grid.width() * grid.height(), 45 * 3);
  EXPECT_GE(grid.origin_m().x(), corner.x());
  EXPECT_NEAR(grid.Probability(grid.CellOf(wall)), options.max_probability, 1e-5);
}

TEST(LidarProbabilityGrid, CompressKeepsEveryCellsProbabilityAndKnownness) {
  const auto walls = testing::RoomWorld();
  ProbabilityGrid grid = testing::RoomMap(walls);
  const ProbabilityGrid original = grid;
  grid.Compress();
  ASSERT_TRUE(grid.compressed());
  EXPECT_TRUE(grid.probabilities().empty());  // the float copy is gone
  EXPECT_EQ(grid.width(), original.width());
  int known = 0;
  for (int y = -2; y < grid.height() + 2; ++y) {
    for (int x = -2; x < grid.width() + 2; ++x) {
      const CellIndex c{x, y};
      ASSERT_EQ(grid.IsKnown(c), original.IsKnown(c)) << x << " " << y;
      ASSERT_NEAR(grid.Probability(c), original.Probability(c), 1e-5) << x << " " << y;
      known += grid.IsKnown(c);
    }
  }
  EXPECT_EQ(known, original.known_cells());
  EXPECT_GT(known, 1000);
}

}  // namespace
}  // namespace groundline::localization::lidar
