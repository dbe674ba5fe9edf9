// The AprilTag adapter: libapriltag's corner order against the printed pattern,
// the half-pixel convention, and the pattern itself.
#include "groundline/calibration/tag_detection.h"

#include <gtest/gtest.h>

#include <cmath>

namespace groundline::calibration {
namespace {

// A tag drawn into a 240 x 240 image, centre c0_px, turned by angle_rad
// (image frame, clockwise on screen), cell_px pixels per cell, box-filtered
// with 8 x 8 samples per pixel. Returns the true corner pixels in the order of
// tag_detection.h (tag frame x right, y up as printed).
std::array<Eigen::Vector2d, 4> DrawTag(const TagPattern& p, double angle_rad, double cell_px,
                                       const Eigen::Vector2d& c0_px, std::vector<std::uint8_t>* im,
                                       int width_px) {
  const double ca = std::cos(angle_rad), sa = std::sin(angle_rad), half = 0.5 * p.total_width;
  im->assign(static_cast<std::size_t>(width_px) * width_px, 0);
  constexpr int kS = 8;
  for (int v = 0; v < width_px; ++v) {
    for (int u = 0; u < width_px; ++u) {
      double sum = 0.0;
      for (int a = 0; a < kS; ++a) {
        for (int b = 0; b < kS; ++b) {
          const double x = u + (a + 0.5) / kS - 0.5 - c0_px.x();
          const double y = v + (b + 0.5) / kS - 0.5 - c0_px.y();
          const double col = (ca * x + sa * y) / cell_px + half;
          const double row = (-sa * x + ca * y) / cell_px + half;
          double value = 128.0;
          if (col >= 0 && row >= 0 && col < p.total_width && row < p.total_width) {
            value = p.Black(static_cast<int>(row), static_cast<int>(col)) ? 20.0 : 235.0;
          }
          sum += value;
        }
      }
      (*im)[static_cast<std::size_t>(v) * width_px + u] =
          static_cast<std::uint8_t>(sum / (kS * kS) + 0.5);
    }
  }
  std::array<Eigen::Vector2d, 4> truth;
  const std::array<Eigen::Vector2d, 4> tag = TagCornersInTagFrame(p.width_at_border * cell_px);
  for (int k = 0; k < 4; ++k) {
    const double col = tag[k].x(), row = -tag[k].y();  // printed y up = image rows down
    truth[k] = c0_px + Eigen::Vector2d(ca * col - sa * row, sa * col + ca * row);
  }
  return truth;
}

TEST(TagDetection, CornerOrderMatchesThePrintedPattern) {
  const TagPattern p = Tag36h11Pattern(3).value();
  constexpr int kW = 240;
  std::vector<std::uint8_t> im;
  Eigen::Vector2d mean_error = Eigen::Vector2d::Zero();
  int n = 0;
  for (const double angle : {0.3, 1.9, -2.6}) {
    for (const double cell : {7.0, 13.0}) {
      const auto truth = DrawTag(p, angle, cell, Eigen::Vector2d(119.3, 121.7), &im, kW);
      const std::vector<TagDetection> found = DetectTags(im.data(), kW, kW, kW);
      ASSERT_EQ(found.size(), 1u) << angle << " " << cell;
      EXPECT_EQ(found[0].id, 3);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d e = found[0].corners_px[k] - truth[k];
        EXPECT_LT(e.norm(), 0.2) << "corner " << k << " angle " << angle << " cell " << cell;
        mean_error += e;
        ++n;
      }
    }
  }
  // The half-pixel convention: no mean offset left.
  EXPECT_LT((mean_error / n).norm(), 0.05) << (mean_error / n).transpose();
}

TEST(TagDetection, PatternHasTheTag36h11Layout) {
  EXPECT_EQ(Tag36h11Count(), 587);
  const TagPattern p = Tag36h11Pattern(0).value();
  ASSERT_EQ(p.total_width, 10);
  ASSERT_EQ(p.width_at_border, 8);
  for (int i = 0; i < 10; ++i) {
    EXPECT_FALSE(p.Black(0, i));  // white outer ring
    EXPECT_FALSE(p.Black(i, 9));
    if (i >= 1 && i <= 8) {
      EXPECT_TRUE(p.Black(1, i));  // black border ring
      EXPECT_TRUE(p.Black(i, 8));
    }
  }
  EXPECT_FALSE(Tag36h11Pattern(587).ok());
  EXPECT_FALSE(Tag36h11Pattern(-1).ok());
}

TEST(TagDetection, FindsNothingInAFlatImage) {
  std::vector<std::uint8_t> im(100 * 80, 128);
  EXPECT_TRUE(DetectTags(im.data(), 100, 80, 100).empty());
  TagDetectorOptions bad;
  bad.quad_decimate = 0.5;
  EXPECT_FALSE(bad.Validate().ok());
}

}  // namespace
}  // namespace groundline::calibration
