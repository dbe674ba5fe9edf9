// Loop verification by free space: in a closed corridor, a candidate shifted
// along the aisle scores as well as a loop match needs to (the side walls
// fit) but puts returns where the map has seen through and rays through the
// end wall: rejected. The true pose is accepted, also with a forklift in
// front of the robot that the map does not have.
#include "groundline/localization/lidar/loop_verification.h"

#include <gtest/gtest.h>

#include "groundline/localization/lidar/scan_matcher.h"
#include "lidar_test_world.h"

namespace groundline::localization::lidar {
namespace {

// A 3 m wide corridor from x = -6 to x = 6 with closed ends.
std::vector<testing::Segment> ClosedCorridor() {
  std::vector<testing::Segment> walls;
  testing::AddBox(&walls, -6.0, -1.5, 6.0, 1.5);
  return walls;
}

// The corridor mapped from four poses along it (grid frame = world frame).
ProbabilityGrid CorridorMap(const std::vector<testing::Segment>& walls) {
  ProbabilityGrid grid({}, core::Vector2(-1.0, -1.0));
  for (int k = 0; k < 4; ++k) {
    const core::SE2 pose(-4.5 + 3.0 * k, 0.2 * (k % 2), 0.1 * k);
    const ScanPoints scan = testing::SimulateScan(walls, pose, 0.005, 30 + k);
    std::vector<core::Vector2> hits;
    for (const ScanPoint& p : scan.points) hits.push_back(pose * p.point_m);
    for (int repeat = 0; repeat < 10; ++repeat) grid.InsertScan(pose.translation(), hits);
  }
  return grid;
}

class LidarLoopVerification : public ::testing::Test {
 protected:
  const std::vector<testing::Segment> walls_ = ClosedCorridor();
  const ProbabilityGrid map_ = CorridorMap(walls_);
  const core::SE2 truth_{-4.0, 0.3, 0.1};
};

TEST_F(LidarLoopVerification, AcceptsTrueRevisit) {
  const ScanPoints scan = testing::SimulateScan(walls_, truth_, 0.01, 41);
  const FreeSpaceCheck check = CheckFreeSpace(map_, scan, truth_, FreeSpaceCheckOptions{});
  EXPECT_TRUE(check.consistent) << check.violation_fraction;
  EXPECT_GT(check.rays, 80);
  EXPECT_LT(check.violation_fraction, 0.03);  // 0.01
}

TEST_F(LidarLoopVerification, RejectsAliasedCandidateThatScoresWell) {
  const ScanPoints scan = testing::SimulateScan(walls_, truth_, 0.01, 42);
  const core::SE2 aliased = core::SE2(1.5, 0.0, 0.0) * truth_;  // 1.5 m along the aisle
  // The returns on the side walls still fit: a score a loop match accepts.
  EXPECT_GT(ScoreAt(map_, testing::Positions(scan), aliased), 0.6);
  const FreeSpaceCheck check = CheckFreeSpace(map_, scan, aliased, FreeSpaceCheckOptions{});
  EXPECT_FALSE(check.consistent) << check.violation_fraction;  // 0.26
  EXPECT_GT(check.returns_in_free, 0);        // the near end wall, in the seen-through aisle
  EXPECT_GT(check.rays_through_occupied, 0);  // rays through the far end wall
}

TEST_F(LidarLoopVerification, PassingForkliftDoesNotVetoTrueRevisit) {
  std::vector<testing::Segment> with_forklift = walls_;
  testing::AddBox(&with_forklift, -1.5, -0.2, -0.5, 0.6);  // 2.5 m ahead, not in the map
  const ScanPoints scan = testing::SimulateScan(with_forklift, truth_, 0.01, 43);
  const FreeSpaceCheck check = CheckFreeSpace(map_, scan, truth_, FreeSpaceCheckOptions{});
  EXPECT_GT(check.returns_in_free, 0);                        // the forklift is seen
  EXPECT_TRUE(check.consistent) << check.violation_fraction;  // 0.05
}

TEST(LidarFreeSpaceCheckOptions, Validates) {
  EXPECT_TRUE(FreeSpaceCheckOptions{}.Validate().ok());
  FreeSpaceCheckOptions bad;
  bad.occupied_probability = 0.4;
  EXPECT_FALSE(bad.Validate().ok());
  bad = {};
  bad.max_violation_fraction = 1.5;
  EXPECT_FALSE(bad.Validate().ok());
}

}  // namespace
}  // namespace groundline::localization::lidar
