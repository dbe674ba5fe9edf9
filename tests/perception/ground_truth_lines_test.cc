// Visible map markings as base_link lines, and the matching of extracted
// lines to them.
#include "groundline/perception/ground_truth_lines.h"
#include "test_units.h"

#include <gtest/gtest.h>

#include <numbers>

namespace groundline::perception {
namespace {

using ::groundline::testing::kPi;

core::FloorMap TestMap() {
  core::FloorMap map;
  core::FloorMarking tape;
  tape.id = 1;
  tape.width_m = 0.075;
  tape.polyline_m = {core::Vector2(0.0, 1.0), core::Vector2(10.0, 1.0)};
  map.markings.push_back(tape);
  core::FloorMarking dashed = tape;
  dashed.id = 2;
  dashed.kind = core::MarkingKind::kTapeDashed;
  dashed.dash_m = 0.5;
  dashed.gap_m = 1.5;
  dashed.polyline_m = {core::Vector2(0.0, 0.0), core::Vector2(10.0, 0.0)};
  map.markings.push_back(dashed);
  return map;
}

bool Footprint(const Eigen::Vector2d& p) {
  return p.x() >= 0.6 && p.x() <= 2.4 && std::abs(p.y()) <= 1.0;
}

TEST(GroundTruthLines, VisibleMarkingsInBaseLink) {
  const core::SE2 T_map_base(2.0, 0.7, 0.0);
  const std::vector<TrueLine> lines =
      VisibleMarkingLines(TestMap(), T_map_base, Footprint, VisibleLineOptions{});
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].marking_id, 1);
  EXPECT_NEAR(lines[0].line.rho_m, 0.3, 1e-12);
  EXPECT_NEAR(lines[0].line.alpha_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(lines[0].seen_length_m, 1.8, 0.02);
  EXPECT_NEAR(lines[0].evaluated_length_m, 1.4, 0.02);  // x 1.0 .. 2.4
  EXPECT_TRUE(lines[0].evaluated);
  // Dashes at map x 0-0.5, 2-2.5, 4-4.5: base x 0-0.5 (unseen) and 0.6 .. 2.4
  // holds only base x 2.0-2.4 (the dash at map 4.0-4.4).
  EXPECT_EQ(lines[1].marking_id, 2);
  EXPECT_NEAR(lines[1].line.rho_m, 0.7, 1e-12);
  EXPECT_NEAR(lines[1].line.alpha_rad, -kPi / 2, 1e-12);
  EXPECT_NEAR(lines[1].seen_length_m, 0.4, 0.02);
  EXPECT_TRUE(lines[1].evaluated);
  EXPECT_NEAR(lines[1].start_m.x(), 2.0, 0.011);

  // Facing +y from (1.5, 0), the tape (map y = 1) runs across the vehicle at
  // base x = 1; the dashed line (map y = 0) runs through base_link, unseen.
  const std::vector<TrueLine> turned =
      VisibleMarkingLines(TestMap(), core::SE2(1.5, 0.0, kPi / 2), Footprint, VisibleLineOptions{});
  ASSERT_EQ(turned.size(), 1u);
  EXPECT_NEAR(turned[0].line.rho_m, 1.0, 1e-9);
  EXPECT_NEAR(std::abs(std::cos(turned[0].line.alpha_rad)), 1.0, 1e-9);
  EXPECT_TRUE(turned[0].evaluated);  // 2 m of it crosses the footprint at x = 1.0
}

// A 50 cm stripe is two edges: the centre line where both are seen, else the
// one edge in view.
TEST(GroundTruthLines, WideStripeHalfOutOfViewIsItsEdge) {
  core::FloorMap map;
  core::FloorMarking stripe;
  stripe.id = 7;
  stripe.kind = core::MarkingKind::kCrosswalkStripe;
  stripe.width_m = 0.5;
  stripe.polyline_m = {core::Vector2(0.0, -0.9), core::Vector2(10.0, -0.9)};
  map.markings.push_back(stripe);
  // Edges at y = -0.65 (left of +x, in view) and -1.15 (out of view).
  const std::vector<TrueLine> half =
      VisibleMarkingLines(map, core::SE2(0.0, 0.0, 0.0), Footprint, VisibleLineOptions{});
  ASSERT_EQ(half.size(), 1u);
  EXPECT_EQ(half[0].edge, 1);
  EXPECT_TRUE(half[0].evaluated);
  EXPECT_NEAR(half[0].line.rho_m, 0.65, 1e-12);
  EXPECT_NEAR(half[0].line.alpha_rad, -kPi / 2, 1e-12);
  EXPECT_NEAR(half[0].evaluated_length_m, 1.4, 0.02);
  EXPECT_NEAR(half[0].start_m.y(), -0.65, 1e-12);

  // Moved 0.4 m to the right: both edges in view, the centre line counts; the
  // edges are there to be matched, not evaluated.
  const std::vector<TrueLine> whole =
      VisibleMarkingLines(map, core::SE2(0.0, -0.4, 0.0), Footprint, VisibleLineOptions{});
  ASSERT_EQ(whole.size(), 3u);
  EXPECT_EQ(whole[0].edge, 0);
  EXPECT_TRUE(whole[0].evaluated);
  EXPECT_NEAR(whole[0].line.rho_m, 0.5, 1e-12);
  EXPECT_EQ(whole[1].edge, 1);
  EXPECT_FALSE(whole[1].evaluated);
  EXPECT_NEAR(whole[1].line.rho_m, 0.25, 1e-12);
  EXPECT_EQ(whole[2].edge, -1);
  EXPECT_FALSE(whole[2].evaluated);

  // Turned 0.15 rad to the left: the right edge leaves the footprint's side
  // after 0.33 m, the left one is seen over 1.83 m; both edges overlap over
  // less than half of the longer one, so the left edge counts.
  const std::vector<TrueLine> oblique =
      VisibleMarkingLines(map, core::SE2(0.0, -0.3, 0.15), Footprint, VisibleLineOptions{});
  ASSERT_EQ(oblique.size(), 3u);
  EXPECT_NEAR(oblique[0].seen_length_m, 0.33, 0.02);
  EXPECT_NEAR(oblique[1].seen_length_m, 1.83, 0.02);
  EXPECT_FALSE(oblique[0].evaluated);
  EXPECT_TRUE(oblique[1].evaluated);
  EXPECT_FALSE(oblique[2].evaluated);
}

// A joint running under dashed tape is seen only between the dashes; one
// beside the tape (off it by more than its half width) is seen everywhere.
TEST(GroundTruthLines, TapeOccludesJointUnderItsDashes) {
  core::FloorMap map;
  core::FloorMarking dashed;
  dashed.id = 1;
  dashed.kind = core::MarkingKind::kTapeDashed;
  dashed.width_m = 0.1;
  dashed.dash_m = 1.0;
  dashed.gap_m = 1.0;
  dashed.polyline_m = {core::Vector2(0.0, 0.0), core::Vector2(10.0, 0.0)};
  map.markings.push_back(dashed);
  core::FloorMarking joint;
  joint.id = 2;
  joint.kind = core::MarkingKind::kJoint;
  joint.polarity = core::MarkingPolarity::kDark;
  joint.width_m = 0.008;
  joint.polyline_m = {core::Vector2(0.0, 0.0), core::Vector2(10.0, 0.0)};
  map.markings.push_back(joint);
  core::FloorMarking beside = joint;
  beside.id = 3;
  beside.polyline_m = {core::Vector2(0.0, 0.06), core::Vector2(10.0, 0.06)};
  map.markings.push_back(beside);
  // Base x 0.6 .. 2.4 is map x 1.6 .. 3.4: a gap up to 2.0, a dash 2.0-3.0,
  // a gap from 3.0.
  const core::SE2 T_map_base(1.0, 0.0, 0.0);
  const std::vector<TrueLine> lines =
      VisibleMarkingLines(map, T_map_base, Footprint, VisibleLineOptions{});
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[1].marking_id, 2);
  EXPECT_NEAR(lines[1].seen_length_m, 0.8, 0.025);       // 0.4 + 0.4 between dashes
  EXPECT_NEAR(lines[1].evaluated_length_m, 0.4, 0.025);  // base x 2.0 .. 2.4
  EXPECT_TRUE(lines[1].evaluated);
  EXPECT_EQ(lines[2].marking_id, 3);
  EXPECT_NEAR(lines[2].seen_length_m, 1.8, 0.02);

  // The definition before the audit sees the joint under the dash too.
  VisibleLineOptions old_definition;
  old_definition.tape_occludes_joints = false;
  const std::vector<TrueLine> old_lines =
      VisibleMarkingLines(map, T_map_base, Footprint, old_definition);
  ASSERT_EQ(old_lines.size(), 3u);
  EXPECT_NEAR(old_lines[1].seen_length_m, 1.8, 0.02);

  // Under solid tape the joint is not seen at all; the one beside it is.
  map.markings[0].kind = core::MarkingKind::kTapeSolid;
  map.markings[0].dash_m.reset();
  map.markings[0].gap_m.reset();
  const std::vector<TrueLine> covered =
      VisibleMarkingLines(map, T_map_base, Footprint, VisibleLineOptions{});
  ASSERT_EQ(covered.size(), 2u);
  EXPECT_EQ(covered[0].marking_id, 1);
  EXPECT_EQ(covered[1].marking_id, 3);
}

TEST(GroundTruthLines, MatchGatesOverlapAndDuplicates) {
  TrueLine truth;
  truth.line = {0.3, kPi / 2};
  truth.start_m = {1.0, 0.3};
  truth.end_m = {2.0, 0.3};
  truth.evaluated = true;
  const std::vector<TrueLine> truths = {truth};
  auto segment = [](double rho, double alpha, double x0, double x1) {
    LineSegmentEstimate s;
    s.line = NormalizeLine(rho, alpha);
    const Eigen::Vector2d foot = s.line.rho_m * s.line.Normal();
    const Eigen::Vector2d d = s.line.Direction();
    s.start_m = foot + (x0 - foot.x()) / d.x() * d;
    s.end_m = foot + (x1 - foot.x()) / d.x() * d;
    return s;
  };
  const std::vector<LineSegmentEstimate> extracted = {
      segment(0.32, kPi / 2, 1.2, 1.8),           // within 5 cm: match
      segment(0.301, kPi / 2 + 0.001, 1.1, 1.9),  // closer: the match; the first is a duplicate
      segment(0.36, kPi / 2, 1.2, 1.8),           // 6 cm off
      segment(0.3, kPi / 2 + 0.06, 1.2, 1.8),     // 3.4 deg off
      segment(0.3, kPi / 2, 2.2, 2.6),            // no overlap
      segment(-0.3, -kPi / 2, 1.2, 1.8)};         // the same line, other description
  const LineMatches m = MatchLines(extracted, truths, MatchGates{});
  EXPECT_EQ(m.extracted_of_truth[0], 5);  // LineDifference is 0 in either description
  EXPECT_EQ(m.truth_of_extracted, (std::vector<int>{-1, -1, -1, -1, -1, 0}));
}

}  // namespace
}  // namespace groundline::perception
