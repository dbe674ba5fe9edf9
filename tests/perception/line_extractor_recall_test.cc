// Recall cases of the line extractor found on the simulator datasets (issue
// 4): the Hough segments of a ridge running along the BEV grid half a cell
// off the cell centres (its centres alternate between two columns), and a stripe's single
// edge whose one-sided ridge is shorter than the edge.
#include <gtest/gtest.h>

#include <algorithm>

#include "groundline/perception/line_extractor.h"
#include "groundline/perception/ridge_segments.h"
#include "rendered_bev.h"

namespace groundline::perception {
namespace {

// The centres of a ridge running along the grid half a cell off the cell
// centres (an 8 mm joint at y = 0.5 m in zone C): non-maximum suppression
// puts them in runs of 5-20 cells on either neighbouring column. The Hough
// walk along one pixel column must bridge the runs on the other.
TEST(LineExtractorRecall, HoughBridgesCentresAlternatingBetweenColumns) {
  cv::Mat centres(180, 200, CV_8U, cv::Scalar(0));
  // As measured on zone C seed 1, frame 48: shorter runs on one column.
  const int runs[] = {10, 14, 6, 7, 8, 12, 5, 15, 7, 11, 6, 13, 8, 9, 6, 12};
  int row = 20, column = 50;
  for (const int run : runs) {
    for (int k = 0; k < run && row < 160; ++k) centres.at<std::uint8_t>(row++, column) = 255;
    column = column == 49 ? 50 : 49;
  }
  auto longest = [&](const RidgeSegmentOptions& options) {
    double length = 0.0;
    for (const RidgeSegment& s : MergeCollinearSegments(HoughSegments(centres, options), options)) {
      length = std::max(length, s.Length());
    }
    return length;
  };
  EXPECT_GT(longest(RidgeSegmentOptions{}), 120.0);  // of 140 cells
  // With the former gap of 4 cells the walk breaks at the switches into
  // pieces shorter than hough_min_length_cells.
  RidgeSegmentOptions former;
  former.hough_max_gap_cells = 4.0;
  EXPECT_LT(longest(former), 40.0);
}

// A 50 cm stripe ending 1.36 m ahead whose outer edge is beyond the seen
// floor: its inner edge is seen over ~0.66 m, more than the 0.6 m a single
// edge needs, but the one-sided ridge 3-4 cm inside fades near the stripe's
// corner and the footprint's border. The edge is followed past the ridge.
TEST(LineExtractorRecall, StripeEdgeLongerThanItsRidgeIsFound) {
  const BevGrid grid(BevGridOptions{});
  // Inner edge at y = -0.7, square end at x = 1.36.
  const Floor stripe = [](const Eigen::Vector2d& p) {
    return p.x() <= 1.36 && p.y() <= -0.7 ? 200.0 : 80.0;
  };
  const cv::Mat bev = RenderBev(grid, stripe);
  auto edges = [&](const LineExtractor& extractor) {
    std::vector<ExtractedLine> found;
    for (const ExtractedLine& l : extractor.Extract(bev).lines) {
      if (l.single_bar_edge) found.push_back(l);
    }
    return found;
  };
  const std::vector<ExtractedLine> found = edges(MakeExtractor(grid));
  ASSERT_EQ(found.size(), 1u);
  const Eigen::Vector2d r = LineDifference(found[0].line, NormalizeLine(0.7, -kPi / 2));
  EXPECT_LT(std::abs(r(0)), 0.003);
  EXPECT_LT(std::abs(r(1)), 0.2 * kPi / 180);
  EXPECT_GT(found[0].LengthM(), 0.6);

  // Without following the edge past the ridge it is shorter or missing.
  LineExtractorOptions ridge_only;
  ridge_only.single_edge_extension_m = 0.0;
  const std::vector<ExtractedLine> short_edges = edges(MakeExtractor(grid, ridge_only));
  const double ridge_only_m = short_edges.empty() ? 0.0 : short_edges[0].LengthM();
  EXPECT_GT(found[0].LengthM(), ridge_only_m + 0.05);
}

}  // namespace
}  // namespace groundline::perception
