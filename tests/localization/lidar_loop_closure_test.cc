// Loop closure: the branch-and-bound search finds a true revisit from a
// metres-off estimate and finds nothing for a scan of another place; in a
// rack aisle it reports the next bay as a runner-up, in a room none; the
// pose graph keeps a consistent loop constraint and rejects a wrong one, and
// does not judge a loop in a direction its information leaves out.
#include "groundline/localization/lidar/loop_closure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "groundline/localization/lidar/pose_graph.h"
#include "groundline/localization/lidar/scan_aliasing.h"
#include "groundline/localization/lidar/scan_matcher.h"
#include "lidar_test_world.h"
#include "test_units.h"

namespace groundline::localization::lidar {
namespace {

using ::groundline::testing::kDeg;

TEST(LidarBranchAndBound, FindsTrueRevisitFromMetresOffEstimate) {
  const auto walls = testing::RoomWorld();
  const ProbabilityGrid grid = testing::RoomMap(walls);
  const PrecomputedGrids precomputed(grid, BranchAndBoundOptions{}.depth);
  const core::SE2 truth(0.8, -1.2, 2.5);
  const ScanPoints scan = testing::SimulateScan(walls, truth, 0.01, 21);
  const core::SE2 estimate = truth * core::SE2(1.6, -1.1, 12.0 * kDeg);
  const std::optional<BranchAndBoundMatch> found = BranchAndBoundSearch(
      grid, precomputed, testing::Positions(scan), estimate, 0.6, BranchAndBoundOptions{});
  ASSERT_TRUE(found.has_value());
  const core::SE2 coarse_error = truth.Between(found->T_grid_base);
  EXPECT_LT(coarse_error.translation().norm(), 0.06);
  EXPECT_LT(std::abs(coarse_error.yaw()), 0.6 * kDeg);
  // Exactness: no discrete pose near the truth scores higher (brute force).
  EXPECT_GE(found->score + 1.0 / 255.0,
            ScoreAt(grid, testing::Positions(scan), found->T_grid_base) - 1e-3);
  core::Result<ScanMatchResult> refined = MatchScan(
      grid, testing::Positions(scan), found->T_grid_base, ScanMatcherOptions{}, found->T_grid_base);
  ASSERT_TRUE(refined.ok());
  const core::SE2 error = truth.Between(refined->T_grid_base);
  EXPECT_LT(error.translation().norm(), 0.02);
  EXPECT_LT(std::abs(error.yaw()), 0.3 * kDeg);
}

TEST(LidarBranchAndBound, FindsNothingForAnotherPlace) {
  const ProbabilityGrid grid = testing::RoomMap(testing::RoomWorld());
  const PrecomputedGrids precomputed(grid, BranchAndBoundOptions{}.depth);
  std::vector<testing::Segment> other;  // an L-shaped hall of other proportions
  testing::AddBox(&other, -2.0, -6.0, 2.5, 6.0);
  other.push_back({{-2.0, 1.0}, {0.5, 1.0}});
  const ScanPoints scan = testing::SimulateScan(other, {0.2, -2.0, 0.3}, 0.01, 22);
  const std::optional<BranchAndBoundMatch> found = BranchAndBoundSearch(
      grid, precomputed, testing::Positions(scan), {0.0, 0.0, 0.0}, 0.6, BranchAndBoundOptions{});
  EXPECT_FALSE(found.has_value()) << found->score;
}

TEST(LidarBranchAndBound, ReportsTheNextBayOfARackAisleAsARunnerUp) {
  const auto aisle = testing::AisleWorld(-40.0, 40.0);
  std::vector<core::SE2> poses;
  for (double x = -6.0; x <= 6.0; x += 1.5) poses.push_back({x, 0.05, 0.0});
  const ProbabilityGrid grid = testing::MapFromScans(aisle, poses, {-40.0, -3.0});
  BranchAndBoundOptions options;
  options.runner_up_distance_m = 0.5;
  const PrecomputedGrids precomputed(grid, options.depth);
  const core::SE2 truth(0.6, -0.1, 0.02);
  const ScanPoints scan = testing::SimulateScan(aisle, truth, 0.01, 31);
  const std::optional<BranchAndBoundMatch> found = BranchAndBoundSearch(
      grid, precomputed, testing::Positions(scan), truth * core::SE2(0.3, 0.1, 0.0), 0.6, options);
  ASSERT_TRUE(found.has_value());
  ASSERT_TRUE(found->runner_up.has_value()) << "best " << found->score;
  EXPECT_GE(found->runner_up->score, options.runner_up_min_ratio * found->score);
  EXPECT_LE(found->runner_up->score, found->score);
  // One bay along the aisle from the best, which is one of the two.
  const core::Vector2 between =
      found->runner_up->T_grid_base.translation() - found->T_grid_base.translation();
  EXPECT_NEAR(std::abs(between.x()), testing::kPitchM, 0.15);
  EXPECT_LT(std::abs(between.y()), 0.15);
  const double best_off = std::abs(truth.Between(found->T_grid_base).x());
  const double second_off = std::abs(truth.Between(found->runner_up->T_grid_base).x());
  EXPECT_LT(std::min(best_off, second_off), 0.1);
}

TEST(LidarBranchAndBound, FindsNoRunnerUpInARoom) {
  const auto walls = testing::RoomWorld();
  const ProbabilityGrid grid = testing::RoomMap(walls);
  BranchAndBoundOptions options;
  options.runner_up_distance_m = 0.5;
  const PrecomputedGrids precomputed(grid, options.depth);
  const core::SE2 truth(0.8, -1.2, 2.5);
  const ScanPoints scan = testing::SimulateScan(walls, truth, 0.01, 21);
  const std::optional<BranchAndBoundMatch> found =
      BranchAndBoundSearch(grid, precomputed, testing::Positions(scan),
                           truth * core::SE2(1.6, -1.1, 12.0 * kDeg), 0.6, options);
  ASSERT_TRUE(found.has_value());
  EXPECT_LT(truth.Between(found->T_grid_base).translation().norm(), 0.06);
  EXPECT_FALSE(found->runner_up.has_value()) << found->runner_up->score << " of " << found->score;
}

TEST(LidarPoseGraph, DoesNotJudgeALoopAlongADirectionItsInformationLeavesOut) {
  // Five nodes 1 m apart along x, exact odometry; a loop to node 4 that is a
  // bay (2.7 m) off along x and exact across and in heading.
  auto graph_with_loop = [](const core::Matrix3& loop_sqrt) {
    PoseGraph graph(PoseGraphOptions{});
    const core::Matrix3 odometry_sqrt = core::Vector3(100.0, 100.0, 200.0).asDiagonal();
    for (int i = 0; i < 5; ++i) {
      graph.AddNode(core::SE2(i, 0.0, 0.0));
      if (i > 0) {
        graph.AddConstraint(
            {ConstraintKind::kOdometry, i - 1, i, core::SE2(1.0, 0.0, 0.0), odometry_sqrt});
      }
    }
    graph.AddSubmap(core::SE2());
    graph.AddConstraint(
        {ConstraintKind::kIntraSubmap, 0, 0, core::SE2(), core::Matrix3::Identity() * 100.0});
    graph.AddConstraint({ConstraintKind::kLoop, 0, 4, core::SE2(4.0 + 2.7, 0.0, 0.0), loop_sqrt});
    return graph;
  };
  const core::Matrix3 match_sqrt = core::Matrix3::Identity() * 100.0;
  // Without information along x (an aliased aisle): kept, and it moves nothing.
  PoseGraph aliased = graph_with_loop(RemoveTranslation(match_sqrt, core::Vector2::UnitX()));
  core::Result<PoseGraphSummary> summary = aliased.Optimize();
  ASSERT_TRUE(summary.ok()) << summary.message();
  EXPECT_EQ(summary->loops_rejected, 0);
  EXPECT_EQ(aliased.num_loops(), 1);
  EXPECT_NEAR(aliased.node(4).translation().x(), 4.0, 1e-6);
  // With full information the same loop is rejected.
  PoseGraph full = graph_with_loop(match_sqrt);
  core::Result<PoseGraphSummary> full_summary = full.Optimize();
  ASSERT_TRUE(full_summary.ok()) << full_summary.message();
  EXPECT_TRUE(full.constraints().back().rejected);
}

TEST(LidarPoseGraph, KeepsConsistentLoopRejectsWrongOne) {
  // A square loop of 8 nodes, 1 m apart; odometry with a yaw bias.
  std::vector<core::SE2> truth;
  for (int i = 0; i < 8; ++i) {
    const int side = i / 2, step = i % 2;
    truth.push_back(core::SE2(0.0, 0.0, side * std::numbers::pi / 2.0) *
                    core::SE2(-1.0 + step * 1.0, -1.0, 0.0));
  }
  PoseGraph graph(PoseGraphOptions{});
  core::SE2 odometry_pose = truth[0];
  const core::Matrix3 odometry_sqrt = core::Vector3(100.0, 100.0, 200.0).asDiagonal();
  for (int i = 0; i < 8; ++i) {
    if (i > 0) {
      const core::SE2 measured = truth[i - 1].Between(truth[i]) * core::SE2(0.0, 0.0, 0.01);
      odometry_pose = odometry_pose * measured;
      graph.AddNode(odometry_pose);
      graph.AddConstraint({ConstraintKind::kOdometry, i - 1, i, measured, odometry_sqrt});
    } else {
      graph.AddNode(truth[0]);
    }
  }
  graph.AddSubmap(truth[0]);
  const core::Matrix3 match_sqrt = core::Matrix3::Identity() * 100.0;
  graph.AddConstraint({ConstraintKind::kIntraSubmap, 0, 0, core::SE2(), match_sqrt});
  graph.AddConstraint(
      {ConstraintKind::kLoop, 0, 7, truth[0].Between(truth[7]), match_sqrt});  // true revisit
  graph.AddConstraint({ConstraintKind::kLoop, 0, 4,
                       truth[0].Between(truth[4]) * core::SE2(1.5, -1.0, 0.4), match_sqrt});
  core::Result<PoseGraphSummary> summary = graph.Optimize();
  ASSERT_TRUE(summary.ok()) << summary.message();
  EXPECT_EQ(summary->loops_rejected, 1);
  EXPECT_FALSE(graph.constraints()[graph.constraints().size() - 2].rejected);
  EXPECT_TRUE(graph.constraints().back().rejected);
  EXPECT_EQ(graph.num_loops(), 1);
  EXPECT_LT(truth[7].Between(graph.node(7)).translation().norm(), 0.02);
}

}  // namespace
}  // namespace groundline::localization::lidar
