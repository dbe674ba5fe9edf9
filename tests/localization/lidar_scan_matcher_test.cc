// Scan-to-grid matching on exact ray-cast scans of a hand-built room: the
// cost's analytic Jacobians, the accuracy of the match from a 20 cm / 5 deg
// offset, and robustness to an object that was not in the map.
#include "groundline/localization/lidar/scan_matcher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "jacobian_check.h"
#include "lidar_test_world.h"
#include "test_units.h"

namespace groundline::localization::lidar {
namespace {

using ::groundline::testing::kDeg;

using testing::Positions;
using testing::RoomMap;

TEST(LidarGridPointCost, AnalyticJacobiansMatchNumeric) {
  const ProbabilityGrid grid = RoomMap(testing::RoomWorld());
  const GridInterpolator interpolator(grid);
  for (const core::Vector2& p :
       {core::Vector2(3.1, 0.4), core::Vector2(-2.0, 3.9), core::Vector2(0.3, -3.95)}) {
    const GridPointCost cost(&interpolator, p, 0.7);
    for (const core::SE2& T : {core::SE2(0.01, 0.02, 0.01), core::SE2(0.2, -0.1, 0.3)}) {
      Eigen::Matrix<double, 1, 3> J;
      cost.Residual(T, &J);
      auto f = [&cost](const core::SE2& x) { return cost.Residual(x); };
      EXPECT_JACOBIAN_NEAR(J, f, T, 1e-5);
      // Ceres' ambient (x, y, yaw) Jacobian.
      const core::Vector3 x = T.Vector();
      double residual = 0.0, ambient[3];
      const double* parameters[] = {x.data()};
      double* jacobians[] = {ambient};
      ASSERT_TRUE(cost.Evaluate(parameters, &residual, jacobians));
      EXPECT_NEAR(residual, cost.Residual(T), 1e-12);
      auto g = [&cost](const core::Vector3& v) {
        return cost.Residual(core::SE2(v(0), v(1), v(2)));
      };
      const Eigen::RowVector3d J_ambient(ambient[0], ambient[1], ambient[2]);
      EXPECT_JACOBIAN_NEAR(J_ambient, g, x, 1e-5);
    }
  }
}

TEST(LidarScanMatcher, RecoversPoseFromTwentyCentimetreFiveDegreeOffset) {
  const auto walls = testing::RoomWorld();
  const ProbabilityGrid grid = RoomMap(walls);
  ScanMatcherOptions options;
  options.linear_window_m = 0.3;
  options.angular_window_rad = 8.0 * kDeg;
  const core::SE2 truths[] = {{0.4, 0.3, 0.2}, {-1.5, -0.5, 2.0}, {2.5, 2.0, -1.0}};
  for (unsigned k = 0; k < 3; ++k) {
    const core::SE2& truth = truths[k];
    const ScanPoints scan = testing::SimulateScan(walls, truth, 0.01, 100 + k);
    const core::SE2 prediction = truth * core::SE2(0.16, -0.12, 5.0 * kDeg);
    core::Result<ScanMatchResult> match = MatchScan(grid, Positions(scan), prediction, options);
    ASSERT_TRUE(match.ok()) << match.message();
    const core::SE2 error = truth.Between(match->T_grid_base);
    EXPECT_LT(error.translation().norm(), 0.015) << k;
    EXPECT_LT(std::abs(error.yaw()), 0.2 * kDeg) << k;
    EXPECT_GT(match->score, 0.5);
  }
}

TEST(LidarScanMatcher, PointsOnKnownFreeSpaceAreRejectedAndDoNotBias) {
  auto walls = testing::RoomWorld();
  const ProbabilityGrid grid = RoomMap(walls);   // mapped without the pallet
  testing::AddBox(&walls, 0.8, -0.6, 2.0, 0.6);  // a pallet put down later
  const core::SE2 truth(-0.5, 0.2, 0.1);
  const ScanPoints scan = testing::SimulateScan(walls, truth, 0.01, 7);
  core::Result<ScanMatchResult> match =
      MatchScan(grid, Positions(scan), truth * core::SE2(0.1, 0.05, 0.03), ScanMatcherOptions{});
  ASSERT_TRUE(match.ok()) << match.message();
  EXPECT_GT(match->points_rejected_free, 20);
  const core::SE2 error = truth.Between(match->T_grid_base);
  EXPECT_LT(error.translation().norm(), 0.02);
  EXPECT_LT(std::abs(error.yaw()), 0.3 * kDeg);
}

}  // namespace
}  // namespace groundline::localization::lidar
