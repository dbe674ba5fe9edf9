// The intrinsics verdict on OpenCV's real chessboard views
// (../shared/data/calib/opencv_chessboard): 3 views and the full 13 both
// leave most of the imager unseen and must FAIL with capture advice; the
// uncertainty the report states is what makes the difference visible.
#include <gtest/gtest.h>

#include <algorithm>

#include "calibration_test_views.h"
#include "groundline/calibration/calibration_report.h"

namespace groundline::calibration {
namespace {

bool HasLineStartingWith(const std::vector<std::string>& lines, const std::string& start) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.rfind(start, 0) == 0; });
}

IntrinsicCalibration Solve(const std::vector<CalibrationView>& views) {
  const BoardGrid grid = MakeBoardGrid(testing::TargetNamed("opencv_chessboard_9x6_25mm"));
  core::Result<IntrinsicCalibration> solved =
      CalibrateIntrinsics(views, grid, 640, 480, IntrinsicCalibrationOptions{});
  EXPECT_TRUE(solved.ok()) << solved.message();
  return std::move(solved).value();
}

CalibrationReport Judge(const IntrinsicCalibration& cal) {
  return BuildCalibrationReport(cal, "opencv_chessboard_9x6_25mm", {}, ReportThresholds{});
}

TEST(IntrinsicsVerdictReal, ThreeViewsFailForViewsCoverageAndUncertainty) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const BoardGrid grid = MakeBoardGrid(testing::TargetNamed("opencv_chessboard_9x6_25mm"));
  std::vector<CalibrationView> views = testing::OpenCvLeftViews(grid);
  ASSERT_EQ(views.size(), 13u);
  views.resize(3);  // left01..left03
  const IntrinsicCalibration cal = Solve(views);
  const CalibrationReport report = Judge(cal);
  EXPECT_FALSE(report.pass);
  // The fit itself is good: only the coverage rules can catch this.
  EXPECT_LT(cal.summary.rms_px, 0.3);
  EXPECT_EQ(report.failures[0], "3 views < 20");
  EXPECT_NE(report.advice[0].find("capture 17 more view(s)"), std::string::npos);
  EXPECT_TRUE(HasLineStartingWith(report.failures, "image top-left corner (outer 10%): 0 corners"));
  EXPECT_TRUE(HasLineStartingWith(report.failures, "projection uncertainty at 2.0 m"));
  EXPECT_TRUE(HasLineStartingWith(report.advice,
                                  "capture views with the board pushed into the image's "
                                  "top-left corner"));
}

TEST(IntrinsicsVerdictReal, ThirteenViewsStateTheUncertaintyAndFailForTheEmptyOuterRing) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const BoardGrid grid = MakeBoardGrid(testing::TargetNamed("opencv_chessboard_9x6_25mm"));
  const CalibrationReport report = Judge(Solve(testing::OpenCvLeftViews(grid)));
  EXPECT_FALSE(report.pass);
  EXPECT_EQ(report.failures[0], "13 views < 20");
  // OpenCV's 13 views never reach the outer ring's corners.
  for (int zone : {0, 2, 5, 7}) EXPECT_EQ(report.border_corners[zone], 0) << zone;
  EXPECT_TRUE(
      HasLineStartingWith(report.failures, "image bottom-right corner (outer 10%): 0 corners < 5"));
  // Tilt is fine on these views (the solved boards turn 35-40 deg).
  EXPECT_GT(report.max_tilt_about_vertical_deg, 30.0);
  EXPECT_GT(report.max_tilt_about_horizontal_deg, 30.0);
  EXPECT_FALSE(HasLineStartingWith(report.failures, "most board tilt"));
  // Worst 1-sigma projection uncertainty at 1, 2, 4 m: mrcal 2.2 gives 7.77 px
  // at pixel 9,469 (projection_uncertainty_test.cc); the map's worst cell
  // centre is (10, 470).
  ASSERT_EQ(report.uncertainty.size(), 4u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(report.uncertainty[i].worst_px, 7.75, 0.1) << report.uncertainty[i].range_m;
    EXPECT_EQ(report.uncertainty[i].cells_not_computable, 0);
  }
  // mm grow with the range (face on: px * range / focal length, about).
  EXPECT_NEAR(report.uncertainty[1].worst_mm, 2.0 * report.uncertainty[0].worst_mm,
              0.05 * report.uncertainty[1].worst_mm);
  EXPECT_TRUE(HasLineStartingWith(report.failures, "projection uncertainty at 2.0 m 7.7"));
  // Where the boards were, the camera is known well: the centre cell.
  const UncertaintyMap& map = report.uncertainty_map;
  EXPECT_LT(map.worst_px[12 * map.cells_x + 16], 0.15);
}

}  // namespace
}  // namespace groundline::calibration
