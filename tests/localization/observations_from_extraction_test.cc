// ObservationsFromExtraction: the extractor's lines and junctions reach the
// smoother unchanged in value, with kinds mapped from polarity/orientation,
// and degenerate covariances are dropped and counted.
#include "groundline/localization/observations_from_extraction.h"

#include <gtest/gtest.h>

namespace groundline::localization {
namespace {

perception::ExtractedLine Line(double rho_m, double alpha_rad, perception::LinePolarity polarity,
                               perception::LineOrientation orientation,
                               const Eigen::Matrix2d& covariance) {
  perception::ExtractedLine line;
  line.line = perception::NormalizeLine(rho_m, alpha_rad);
  line.covariance = covariance;
  line.kind = {polarity, orientation};
  line.start_m = {1.0, rho_m};
  line.end_m = {2.0, rho_m};
  return line;
}

TEST(ObservationsFromExtraction, CopiesValuesMapsKindsAndDropsDegenerateCovariances) {
  Eigen::Matrix2d spd;
  spd << 1e-6, 2e-8, 2e-8, 4e-6;
  perception::LineExtraction extraction;
  extraction.lines.push_back(Line(0.9, 1.5707963, perception::LinePolarity::kBright,
                                  perception::LineOrientation::kLongitudinal, spd));
  extraction.lines.push_back(Line(1.6, 0.0, perception::LinePolarity::kBright,
                                  perception::LineOrientation::kTransverse, spd));
  extraction.lines.push_back(Line(2.0, 0.0, perception::LinePolarity::kDark,
                                  perception::LineOrientation::kTransverse, spd));
  extraction.lines.push_back(Line(0.5, 1.5707963, perception::LinePolarity::kDark,
                                  perception::LineOrientation::kLongitudinal,
                                  Eigen::Matrix2d::Zero()));  // a degenerate fit
  perception::ExtractedLine edge = Line(2.3, 0.0, perception::LinePolarity::kBright,
                                        perception::LineOrientation::kTransverse, spd);
  edge.single_bar_edge = true;  // a bar's lone edge: not the atlas's centre line
  extraction.lines.push_back(edge);
  perception::Junction junction;
  junction.point_m = {1.6, 0.9};
  junction.covariance = 1e-6 * Eigen::Matrix2d::Identity();
  extraction.junctions.push_back(junction);
  perception::Junction degenerate = junction;
  degenerate.covariance = Eigen::Matrix2d::Zero();
  extraction.junctions.push_back(degenerate);

  const ConvertedObservations out = ObservationsFromExtraction(12.5, extraction);
  EXPECT_EQ(out.observations.stamp_s, 12.5);
  ASSERT_EQ(out.observations.lines.size(), 3u);
  EXPECT_EQ(out.dropped_lines, 1);
  EXPECT_EQ(out.skipped_bar_edges, 1);
  EXPECT_EQ(out.dropped_junctions, 1);
  EXPECT_EQ(out.observations.lines[0].kind, core::MarkingKind::kTapeSolid);
  EXPECT_EQ(out.observations.lines[1].kind, core::MarkingKind::kStopBar);
  EXPECT_EQ(out.observations.lines[2].kind, core::MarkingKind::kJoint);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(out.observations.lines[i].line_base.rho_m, extraction.lines[i].line.rho_m);
    EXPECT_EQ(out.observations.lines[i].line_base.alpha_rad, extraction.lines[i].line.alpha_rad);
    EXPECT_EQ(out.observations.lines[i].covariance, spd);
    EXPECT_EQ(out.observations.lines[i].endpoint_a_base_m, extraction.lines[i].start_m);
    EXPECT_EQ(out.observations.lines[i].endpoint_b_base_m, extraction.lines[i].end_m);
  }
  ASSERT_EQ(out.observations.junctions.size(), 1u);
  EXPECT_EQ(out.observations.junctions[0].point_base_m, junction.point_m);
}

}  // namespace
}  // namespace groundline::localization
