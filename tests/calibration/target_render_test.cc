// Printable targets: exact tag bits, exact scale, and libapriltag / OpenCV
// finding every tag and corner of the rendered sheets where the layout puts
// them.
#include "groundline/calibration/target_render.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calibration_test_views.h"
#include "groundline/calibration/board_detection.h"

namespace groundline::calibration {
namespace {

TEST(TargetRender, Tag36h11CellsMatchAprilTagRenderingsBitForBit) {
  GROUNDLINE_REQUIRE_DATA("calib/apriltag_renderings/tag36h11/tag36_11_00000.png");
  const std::filesystem::path dir =
      groundline::testing::SharedDataDir() / "calib/apriltag_renderings/tag36h11";
  for (int id = 0; id < 587; ++id) {
    char name[64];
    std::snprintf(name, sizeof(name), "tag36_11_%05d.png", id);
    const cv::Mat png = cv::imread((dir / name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(png.rows, 10) << name;
    ASSERT_EQ(png.cols, 10) << name;
    const std::vector<std::uint8_t> cells = Tag36h11Cells(id);
    int mismatches = 0;
    for (int r = 0; r < 10; ++r) {
      for (int c = 0; c < 10; ++c)
        mismatches += (png.at<std::uint8_t>(r, c) > 127) != (cells[r * 10 + c] == 1);
    }
    EXPECT_EQ(mismatches, 0) << name;
  }
}

// Pixel of a board point (m) on a sheet rasterized at dpi, where the raster
// puts it: RasterizeSheet rounds every edge to a whole pixel boundary, and
// with pixel centres at integers (camera_model.h) boundary n lies at n - 0.5.
Eigen::Vector2d SheetPixel(const TargetSheet& sheet, const Eigen::Vector3d& p_board, double dpi) {
  const double s = dpi / 25.4;
  return {std::round((sheet.origin_x_mm + 1000.0 * p_board.x()) * s) - 0.5,
          std::round((sheet.origin_y_mm + 1000.0 * p_board.y()) * s) - 0.5};
}

TEST(TargetRender, AprilGridSheetIsDetectedWithEveryIdAndCornerWhereTheLayoutPutsIt) {
  const CalibTarget target = testing::TargetNamed("aprilgrid_7x5_38mm_a3");
  core::Result<std::vector<TargetSheet>> sheets = LayoutTarget(target);
  ASSERT_TRUE(sheets.ok()) << sheets.message();
  ASSERT_EQ(sheets->size(), 1u);
  const TargetSheet& sheet = sheets->front();
  EXPECT_EQ(sheet.paper, "A3_landscape");
  constexpr double kDpi = 100.0;
  cv::Mat gray;
  cv::cvtColor(RasterizeSheet(sheet, kDpi), gray, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(gray.cols, 1654);  // 420 mm at 100 dpi
  EXPECT_EQ(gray.rows, 1169);
  const std::vector<TagDetection> tags = DetectTags(gray, BoardTagDetectorOptions());
  ASSERT_EQ(tags.size(), 35u);
  const BoardGrid grid = MakeBoardGrid(target);
  double worst = 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int i = 0; i < 35; ++i) {
    EXPECT_EQ(tags[i].id, i);
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d expected =
          SheetPixel(sheet, grid.Point_board(AprilGridCornerIndex(target, grid, i, k)), kDpi);
      worst = std::max(worst, (tags[i].corners_px[k] - expected).norm());
      mean += (tags[i].corners_px[k] - expected) / 140.0;
    }
  }
  std::printf("mean corner offset %.3f %.3f px, worst %.3f px\n", mean.x(), mean.y(), worst);
  EXPECT_LT(mean.norm(), 0.01);  // no convention offset
  EXPECT_LT(worst, 0.05);
  // And through DetectBoard: all 140 corners with their grid indices.
  core::Result<BoardObservation> obs = DetectBoard(gray, target, grid, BoardDetectionOptions{});
  ASSERT_TRUE(obs.ok()) << obs.message();
  EXPECT_EQ(obs->grid_index.size(), 140u);
}

TEST(TargetRender, ChessboardSheetHasItsInnerCornersWhereTheLayoutPutsThem) {
  const CalibTarget target = testing::TargetNamed("chessboard_9x6_20mm_a4");
  core::Result<std::vector<TargetSheet>> sheets = LayoutTarget(target);
  ASSERT_TRUE(sheets.ok()) << sheets.message();
  const TargetSheet& sheet = sheets->front();
  constexpr double kDpi = 100.0;
  cv::Mat gray;
  cv::cvtColor(RasterizeSheet(sheet, kDpi), gray, cv::COLOR_BGR2GRAY);
  const BoardGrid grid = MakeBoardGrid(target);
  core::Result<BoardObservation> obs = DetectBoard(gray, target, grid, BoardDetectionOptions{});
  ASSERT_TRUE(obs.ok()) << obs.message();
  ASSERT_EQ(obs->corners_px.size(), 54u);
  // OpenCV may start from either end of the symmetric board.
  double worst_forward = 0.0, worst_reverse = 0.0;
  for (int i = 0; i < 54; ++i) {
    // Inner corner (ix, iy) is one square in from the pattern's top-left.
    const Eigen::Vector3d p = grid.Point_board(i) + Eigen::Vector3d(0.02, 0.02, 0.0);
    const Eigen::Vector3d p_rev = grid.Point_board(53 - i) + Eigen::Vector3d(0.02, 0.02, 0.0);
    worst_forward =
        std::max(worst_forward, (obs->corners_px[i] - SheetPixel(sheet, p, kDpi)).norm());
    worst_reverse =
        std::max(worst_reverse, (obs->corners_px[i] - SheetPixel(sheet, p_rev, kDpi)).norm());
  }
  EXPECT_LT(std::min(worst_forward, worst_reverse), 0.6);
}

TEST(TargetRender, FloorSheetsCarryOneDetectableTagEachCentredOnTheMarks) {
  const CalibTarget target = testing::TargetNamed("floor_tags_a4_150mm");
  core::Result<std::vector<TargetSheet>> sheets = LayoutTarget(target);
  ASSERT_TRUE(sheets.ok()) << sheets.message();
  ASSERT_EQ(sheets->size(), 24u);
  for (int i : {0, 13, 23}) {
    const TargetSheet& sheet = (*sheets)[i];
    EXPECT_EQ(sheet.paper, "A4");
    cv::Mat gray;
    cv::cvtColor(RasterizeSheet(sheet, 60.0), gray, cv::COLOR_BGR2GRAY);
    const std::vector<TagDetection> tags = DetectTags(gray, BoardTagDetectorOptions());
    ASSERT_EQ(tags.size(), 1u) << sheet.file_stem;
    EXPECT_EQ(tags[0].id, 100 + i);
    // The tag's centre is where the centre marks meet.
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& c : tags[0].corners_px) centre += c / 4.0;
    const Eigen::Vector2d cross = 0.5 * (SheetPixel(sheet, Eigen::Vector3d::Zero(), 60.0) +
                                         SheetPixel(sheet, Eigen::Vector3d(0.15, 0.15, 0.0), 60.0));
    const double s = 60.0 / 25.4;
    // The red marks run along the centre lines (sheet mm -> px, centres at integers).
    bool mark_on_centre = false;
    for (const SheetPrimitive& p : sheet.primitives) {
      if (p.kind == SheetPrimitive::Kind::kLine && p.rgb == 0xe00000 && p.w_mm == 0.0) {
        mark_on_centre = std::abs(p.x_mm * s - 0.5 - cross.x()) < 0.5 * s;
      }
    }
    EXPECT_TRUE(mark_on_centre);
    EXPECT_LT((centre - cross).norm(), 0.05);
  }
}

TEST(TargetRender, SvgIsInMillimetresWithAHundredMillimetreScaleBar) {
  const CalibTarget target = testing::TargetNamed("aprilgrid_7x5_38mm_a3");
  const std::string svg = SheetToSvg(LayoutTarget(target)->front());
  EXPECT_NE(svg.find("width='420mm' height='297mm' viewBox='0 0 420 297'"), std::string::npos);
  EXPECT_NE(svg.find(">100 mm</text>"), std::string::npos);
  // The ten alternating 10 mm bar segments: 5 black ones.
  int black_segments = 0;
  for (std::size_t at = svg.find("width='10' height='3' fill='#000000'"); at != std::string::npos;
       at = svg.find("width='10' height='3' fill='#000000'", at + 1)) {
    ++black_segments;
  }
  EXPECT_EQ(black_segments, 5);
}

TEST(TargetRender, APatternTooLargeForItsPaperIsRefused) {
  CalibTarget target = testing::TargetNamed("aprilgrid_6x6_88mm");
  target.paper = "A3";
  core::Result<std::vector<TargetSheet>> sheets = LayoutTarget(target);
  ASSERT_FALSE(sheets.ok());
  EXPECT_NE(sheets.message().find("does not fit paper 'A3'"), std::string::npos)
      << sheets.message();
  target.paper = "";
  sheets = LayoutTarget(target);
  ASSERT_TRUE(sheets.ok());
  EXPECT_EQ(sheets->front().paper, "A0");
}

}  // namespace
}  // namespace groundline::calibration
