// Target definitions: parsing, validation messages, and the solver's grid.
#include "groundline/calibration/calib_target.h"

#include <gtest/gtest.h>

#include <set>

namespace groundline::calibration {
namespace {

constexpr char kHeader[] = "format: groundline-calib-targets\nversion: 1\ntargets:\n";

core::Result<std::vector<CalibTarget>> Parse(const std::string& body) {
  return ParseCalibTargets(kHeader + body, "t.yaml");
}

TEST(CalibTarget, AprilGridCornersLieOnTheSolverGridAtTheirMetricPositions) {
  core::Result<std::vector<CalibTarget>> targets = Parse(
      "  - {name: g, type: aprilgrid, family: tag36h11, tags_x: 3, tags_y: 2, "
      "tag_size_m: 0.04, spacing_ratio: 0.3, first_id: 10}\n");
  ASSERT_TRUE(targets.ok()) << targets.message();
  const CalibTarget& t = targets->front();
  const BoardGrid grid = MakeBoardGrid(t);
  EXPECT_DOUBLE_EQ(grid.pitch_m, 0.004);  // a tenth of a tag
  EXPECT_EQ(grid.width_n, 3 * 13 - 3 + 1);
  EXPECT_EQ(grid.height_n, 2 * 13 - 3 + 1);
  EXPECT_EQ(grid.observable.size(), 24u);
  EXPECT_EQ(std::set<int>(grid.observable.begin(), grid.observable.end()).size(), 24u);
  // Tag 14 = row 1, column 1: top-left corner at (1, 1) * 52 mm; libapriltag's
  // corner order bottom-left, bottom-right, top-right, top-left.
  const double x0 = 0.052, y0 = 0.052, s = 0.04;
  const Eigen::Vector3d expected[4] = {
      {x0, y0 + s, 0}, {x0 + s, y0 + s, 0}, {x0 + s, y0, 0}, {x0, y0, 0}};
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((grid.Point_board(AprilGridCornerIndex(t, grid, 14, k)) - expected[k]).norm(), 1e-12)
        << k;
  }
  EXPECT_EQ(AprilGridCornerIndex(t, grid, 9, 0), -1);
  EXPECT_EQ(AprilGridCornerIndex(t, grid, 16, 0), -1);
  EXPECT_NEAR(t.PatternSize_m().x(), 3 * 0.04 + 2 * 0.012, 1e-12);
}

TEST(CalibTarget, ChessboardGridIsItsInnerCorners) {
  core::Result<std::vector<CalibTarget>> targets = Parse(
      "  - {name: c, type: chessboard, inner_corners_x: 9, inner_corners_y: 6, "
      "square_m: 0.025}\n");
  ASSERT_TRUE(targets.ok()) << targets.message();
  const BoardGrid grid = MakeBoardGrid(targets->front());
  EXPECT_EQ(grid.width_n, 9);
  EXPECT_EQ(grid.observable.size(), 54u);
  EXPECT_LT((grid.Point_board(10) - Eigen::Vector3d(0.025, 0.025, 0)).norm(), 1e-15);
}

TEST(CalibTarget, ErrorsNameTheFileTheTargetAndTheField) {
  struct Case {
    std::string body, expected;
  } cases[] = {
      {"  - {name: c, type: chessboard, inner_corners_x: 9, inner_corners_y: 6, square_m: -1}\n",
       "t.yaml: target 'c': field 'square_m': expected > 0, got -1"},
      {"  - {name: c, type: hexboard}\n", "field 'type': expected chessboard"},
      {"  - {name: c, type: chessboard, inner_corners_x: 9, square_m: 1}\n",
       "missing field 'inner_corners_y'"},
      {"  - {name: g, type: aprilgrid, family: tag36h11, tags_x: 3, tags_y: 2, tag_size_m: 0.04, "
       "spacing_ratio: 0.3183098861837907}\n",
       "field 'spacing_ratio'"},
      {"  - {name: f, type: floor_tag_sheet, family: tag36h11, tag_size_m: 0.1, paper: A4, "
       "first_id: 580, count: 10}\n",
       "outside tag36h11's 0..586"},
      {"  - {name: f, type: floor_tag_sheet, family: tag25h9, tag_size_m: 0.1, paper: A4, "
       "count: 1}\n",
       "only tag36h11"},
  };
  for (const Case& c : cases) {
    core::Result<std::vector<CalibTarget>> targets = Parse(c.body);
    ASSERT_FALSE(targets.ok()) << c.body;
    EXPECT_NE(targets.message().find(c.expected), std::string::npos) << targets.message();
  }
  core::Result<std::vector<CalibTarget>> twice = Parse(
      "  - {name: c, type: chessboard, inner_corners_x: 2, inner_corners_y: 2, square_m: 1}\n"
      "  - {name: c, type: chessboard, inner_corners_x: 2, inner_corners_y: 2, square_m: 1}\n");
  EXPECT_NE(twice.message().find("defined twice"), std::string::npos);
  core::Result<CalibTarget> missing = FindCalibTarget({}, "x");
  EXPECT_NE(missing.message().find("no target named 'x'"), std::string::npos);
}

}  // namespace
}  // namespace groundline::calibration
