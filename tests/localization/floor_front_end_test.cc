// The localizer's camera front end (localization/floor_front_end.h): a blank
// frame (covered lens, blacked-out camera) is refused, not read as a floor
// without markings; a frame of the wrong size is refused; a real floor is read.
#include "groundline/localization/floor_front_end.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "groundline/calibration/floor_projection.h"

namespace groundline::localization {
namespace {

FloorFrontEnd ReferenceCamera() {
  const calibration::CameraModel camera =
      calibration::CameraModel::Pinhole(1132.0, 1132.0, 639.5, 511.5, 1280, 1024);
  core::Result<FloorFrontEnd> made = FloorFrontEnd::Create(camera, calibration::CameraMount());
  EXPECT_TRUE(made.ok()) << made.message();
  return std::move(made).value();
}

TEST(FloorFrontEnd, ItsViewIsTheFloorTheCameraSees) {
  const FloorFrontEnd front_end = ReferenceCamera();
  ASSERT_NE(front_end.view(), nullptr);
  const FloorView& view = *front_end.view();
  ASSERT_GE(view.polygon_base_m.size(), 3u);
  // Every seen cell is inside (the hull of their centres), every unseen one
  // more than a cell outside is out.
  const perception::BevRemap& remap = front_end.remap();
  int inside = 0, outside = 0;
  for (int row = 0; row < remap.grid().rows(); row += 7) {
    for (int col = 0; col < remap.grid().cols(); col += 7) {
      const Eigen::Vector2d p = remap.grid().FloorPointOfCell({col, row});
      const double d = view.InsideDistance(p);
      if (remap.valid_mask().at<std::uint8_t>(row, col) != 0) {
        EXPECT_GE(d, -1e-9) << "seen cell " << col << ", " << row;
        ++inside;
      } else if (d > 0.02) {
        ADD_FAILURE() << "unseen cell " << col << ", " << row << " is " << d << " m inside";
      } else {
        ++outside;
      }
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 0);  // the footprint is a trapezoid in its bounding grid
  // The floor behind the vehicle and far to the side is not in view.
  EXPECT_LT(view.InsideDistance({-1.0, 0.0}), 0.0);
  EXPECT_LT(view.InsideDistance({1.5, 5.0}), 0.0);
  // Every observation carries it.
  cv::Mat grey(1024, 1280, CV_8UC1);
  cv::randu(grey, 60, 120);
  const core::Result<ConvertedObservations> seen = front_end.Observe(grey, 1.0);
  ASSERT_TRUE(seen.ok()) << seen.message();
  EXPECT_EQ(seen->observations.view, front_end.view());
}

TEST(FloorView, InsideDistanceAndTheLengthOfASegmentInside) {
  FloorView square;
  square.polygon_base_m = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 2.0}, {0.0, 2.0}};
  EXPECT_NEAR(square.InsideDistance({1.0, 1.0}), 1.0, 1e-12);
  EXPECT_NEAR(square.InsideDistance({0.5, 1.5}), 0.5, 1e-12);
  EXPECT_NEAR(square.InsideDistance({1.0, -0.25}), -0.25, 1e-12);
  EXPECT_NEAR(square.InsideDistance({3.0, 1.0}), -1.0, 1e-12);
  EXPECT_EQ(FloorView().InsideDistance({0.0, 0.0}), -std::numeric_limits<double>::infinity());
  // Clipped by the square shrunk by the margin: [0.25, 1.75] on each axis.
  EXPECT_NEAR(square.LengthInside({-1.0, 1.0}, {3.0, 1.0}, 0.25), 1.5, 1e-12);
  EXPECT_NEAR(square.LengthInside({1.0, 1.0}, {3.0, 1.0}, 0.0), 1.0, 1e-12);
  EXPECT_NEAR(square.LengthInside({-1.0, -1.0}, {3.0, 3.0}, 0.0), 2.0 * std::sqrt(2.0), 1e-12);
  EXPECT_EQ(square.LengthInside({-1.0, 0.1}, {3.0, 0.1}, 0.25), 0.0);  // along, too near an edge
  EXPECT_EQ(square.LengthInside({3.0, 0.0}, {3.0, 2.0}, 0.0), 0.0);    // outside
  EXPECT_EQ(FloorView().LengthInside({0.0, 0.0}, {1.0, 0.0}, 0.0), 0.0);
}

TEST(FloorFrontEnd, RefusesBlankAndMisSizedFramesAndReadsATapeLine) {
  const FloorFrontEnd front_end = ReferenceCamera();
  // The BEV covers the camera's footprint (0.67-2.2 m ahead for this mount).
  const perception::BevGrid& grid = front_end.remap().grid();
  EXPECT_GT(grid.FloorPointOfCell({0.0, 0.0}).x(), 2.0);
  for (const cv::Scalar& level : {cv::Scalar(0), cv::Scalar(255), cv::Scalar(90)}) {
    const cv::Mat blank(1024, 1280, CV_8UC1, level);
    const core::Result<ConvertedObservations> seen = front_end.Observe(blank, 1.0);
    ASSERT_FALSE(seen.ok());
    EXPECT_NE(seen.message().find("blank"), std::string::npos) << seen.message();
  }
  EXPECT_FALSE(front_end.Observe(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), 1.0).ok());

  // Concrete-like noise with a bright 5 cm tape running straight ahead on the
  // floor (drawn through the camera: its image narrows with the range; a band
  // of constant image width would be a post standing on the floor).
  cv::Mat floor(1024, 1280, CV_8UC1);
  cv::RNG rng(7);
  rng.fill(floor, cv::RNG::NORMAL, 110, 6);
  const calibration::FloorProjection projection(front_end.remap().camera(),
                                                front_end.remap().mount());
  std::vector<cv::Point> tape;
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(0.5, -0.025), Eigen::Vector2d(4.0, -0.025),
                                        Eigen::Vector2d(4.0, 0.025), Eigen::Vector2d(0.5, 0.025)}) {
    const core::Result<Eigen::Vector2d> px = projection.PixelOfFloorPoint(corner);
    ASSERT_TRUE(px.ok()) << px.message();
    tape.emplace_back(static_cast<int>(std::lround(px->x())),
                      static_cast<int>(std::lround(px->y())));
  }
  cv::fillConvexPoly(floor, tape, cv::Scalar(230));
  const core::Result<ConvertedObservations> seen = front_end.Observe(floor, 2.0);
  ASSERT_TRUE(seen.ok()) << seen.message();
  EXPECT_GE(seen->observations.lines.size(), 1u);
  EXPECT_EQ(seen->observations.stamp_s, 2.0);
}

// The texture's BEV covers the line BEV's floor at its own finer cells, on
// the same mount, and sees the same floor; a frame of another size is
// refused; another mount gets its own table.
TEST(FloorFrontEnd, TheTextureBevIsTheSameFloorAtFinerCells) {
  const FloorFrontEnd front_end = ReferenceCamera();
  cv::Mat grey(1024, 1280, CV_8UC1);
  cv::randu(grey, 60, 120);
  BevFrame texture{cv::Mat(), cv::Mat(), perception::BevGrid(perception::BevGridOptions{}), {}};
  ASSERT_TRUE(front_end.TextureBev(grey, &texture).ok());
  const perception::BevGrid& lines = front_end.remap().grid();
  EXPECT_DOUBLE_EQ(texture.grid.cell_m(), FloorFrontEndOptions().texture.grid.cell_m);
  EXPECT_LT(texture.grid.cell_m(), lines.cell_m());
  EXPECT_EQ(texture.image.size(), texture.seen.size());
  EXPECT_EQ(texture.image.cols, texture.grid.cols());
  // The same extent: the far left corner exactly, the near right one within
  // a texture cell.
  const Eigen::Vector2d far_left(-0.5, -0.5);
  EXPECT_NEAR((texture.grid.FloorPointOfCell(far_left) - lines.FloorPointOfCell(far_left)).norm(),
              0.0, 1e-9);
  const Eigen::Vector2d near_right =
      lines.FloorPointOfCell({lines.cols() - 0.5, lines.rows() - 0.5});
  EXPECT_LT((texture.grid.FloorPointOfCell({texture.grid.cols() - 0.5, texture.grid.rows() - 0.5}) -
             near_right)
                .cwiseAbs()
                .maxCoeff(),
            texture.grid.cell_m());
  // The same floor seen: seen in one, seen in the other (away from the border).
  int both = 0;
  for (int row = 5; row < texture.grid.rows(); row += 17) {
    for (int col = 5; col < texture.grid.cols(); col += 17) {
      const Eigen::Vector2d c = lines.CellOfFloorPoint(texture.grid.FloorPointOfCell({col, row}));
      const int lc = static_cast<int>(std::lround(c.x())),
                lr = static_cast<int>(std::lround(c.y()));
      if (lc < 1 || lr < 1 || lc >= lines.cols() - 1 || lr >= lines.rows() - 1) continue;
      const bool a = texture.seen.at<std::uint8_t>(row, col) != 0;
      const bool b = front_end.remap().valid_mask().at<std::uint8_t>(lr, lc) != 0;
      const cv::Rect near(lc - 1, lr - 1, 3, 3);
      const int around = cv::countNonZero(front_end.remap().valid_mask()(near));
      if (around == 0 || around == 9) {
        EXPECT_EQ(a, b) << col << ", " << row;
      }
      both += a && b;
    }
  }
  EXPECT_GT(both, 50);
  const core::Status wrong =
      front_end.TextureBev(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), &texture);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.message().find("1280x1024"), std::string::npos) << wrong.message();
  calibration::CameraMount lower = front_end.mount();
  lower.height_m -= 0.01;
  const core::Result<FloorFrontEnd> moved = front_end.WithMount(lower, Eigen::Matrix4d::Zero());
  ASSERT_TRUE(moved.ok()) << moved.message();
  ASSERT_TRUE(moved->TextureBev(grey, &texture).ok());
  EXPECT_DOUBLE_EQ(texture.mount.height_m, lower.height_m);
}

}  // namespace
}  // namespace groundline::localization
