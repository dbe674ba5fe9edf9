// Line extraction next to floor nuisances on rendered BEV images: a tire
// scuff arc or an elongated oil stain is no joint (a joint is a narrow
// groove along most of its length), a tape laid over a joint is one tape, a
// joint partly under an oil stain is still found.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "groundline/perception/line_extractor.h"
#include "rendered_bev.h"

namespace groundline::perception {
namespace {

int CountLines(const LineExtraction& out, LinePolarity polarity) {
  return static_cast<int>(
      std::count_if(out.lines.begin(), out.lines.end(),
                    [&](const ExtractedLine& l) { return l.kind.polarity == polarity; }));
}

// A dark streak 40 grey levels deep with soft (cosine) edges, half_width_m
// to either side of its centre line: along an arc of radius 2 m (a turning
// tire's scuff), or straight; 1 m long, passing (1.5, 0) heading +x.
Floor Streak(double half_width_m, bool arc, double concrete = 80.0) {
  const Eigen::Vector2d centre(1.5, -2.0);
  return [=](const Eigen::Vector2d& p) {
    double across = 0.0;
    if (arc) {
      const Eigen::Vector2d v = p - centre;
      if (std::abs(std::atan2(v.x(), v.y())) > 0.25) return concrete;  // 0.5 rad * 2 m
      across = std::abs(v.norm() - 2.0);
    } else {
      if (std::abs(p.x() - 1.5) > 0.5) return concrete;
      across = std::abs(p.y());
    }
    if (across > half_width_m) return concrete;
    return concrete - 40.0 * 0.5 * (1.0 + std::cos(kPi * across / half_width_m));
  };
}

// As narrow as a joint (1.5 cm at half depth), but curved: the straightness
// tests reject it, each on its own (the sagitta's bound, and the arc test).
TEST(LineExtractorNuisance, ScuffArcGivesNoLine) {
  const BevGrid grid(BevGridOptions{});
  const cv::Mat bev = RenderBev(grid, Streak(0.015, true));
  ExpectNoLines(MakeExtractor(grid).Extract(bev), "a scuff arc");
  LineExtractorOptions no_bound;
  no_bound.max_dark_sagitta_m = 1.0;
  ExpectNoLines(MakeExtractor(grid, no_bound).Extract(bev), "a scuff arc, arc test alone");
  LineExtractorOptions no_arc;
  no_arc.dark_arc_max_radius_m = 0.0;
  ExpectNoLines(MakeExtractor(grid, no_arc).Extract(bev), "a scuff arc, sagitta bound alone");
  LineExtractorOptions neither = no_bound;
  neither.dark_arc_max_radius_m = 0.0;
  EXPECT_GE(CountLines(MakeExtractor(grid, neither).Extract(bev), LinePolarity::kDark), 1);
}

// Straight and as dark as a joint, but 4 cm wide at half depth: the
// narrowness test rejects it.
TEST(LineExtractorNuisance, WideDarkStreakIsNoJoint) {
  const BevGrid grid(BevGridOptions{});
  const cv::Mat bev = RenderBev(grid, Streak(0.04, false));
  ExpectNoLines(MakeExtractor(grid).Extract(bev), "a wide streak");
  LineExtractorOptions options;
  options.min_dark_narrow_share = 0.0;
  EXPECT_GE(CountLines(MakeExtractor(grid, options).Extract(bev), LinePolarity::kDark), 1);
}

TEST(LineExtractorNuisance, OilStainBesideAJointGivesOnlyTheJoint) {
  const BevGrid grid(BevGridOptions{});
  const Tape joint{{0.6, 0.2}, {2.4, 0.2}, 0.01, 25.0};
  // An elongated stain, 8 cm x 50 cm, darkening the concrete by 40 %, along
  // the joint, its edge 2 cm from it.
  const Tape stain{{1.3, 0.14}, {1.8, 0.14}, 0.08, 48.0};
  const LineExtraction out = MakeExtractor(grid).Extract(RenderBev(grid, Paint({joint, stain})));
  ASSERT_EQ(out.lines.size(), 1u);
  EXPECT_EQ(out.lines[0].kind.polarity, LinePolarity::kDark);
  EXPECT_NEAR(out.lines[0].line.rho_m, 0.2, 0.003);
  EXPECT_GT(out.lines[0].LengthM(), 1.2);
}

TEST(LineExtractorNuisance, TapeOverAJointIsOneTape) {
  const BevGrid grid(BevGridOptions{});
  // A 10 cm tape laid over a joint: the joint's groove splits it in two
  // bright ridges 4-5 cm apart.
  const Tape joint{{0.6, -0.3}, {2.4, -0.3}, 0.015, 40.0};
  const Tape tape{{0.9, -0.3}, {2.1, -0.3}, 0.10, 180.0};
  const cv::Mat bev = RenderBev(grid, Paint({joint, tape}));
  LineExtractorOptions unmerged;
  unmerged.same_marking_distance_m = 0.0;
  EXPECT_EQ(CountLines(MakeExtractor(grid, unmerged).Extract(bev), LinePolarity::kBright), 2);
  const LineExtraction out = MakeExtractor(grid).Extract(bev);
  ASSERT_EQ(CountLines(out, LinePolarity::kBright), 1);
  for (const ExtractedLine& l : out.lines) {
    if (l.kind.polarity != LinePolarity::kBright) continue;
    EXPECT_NEAR(l.line.rho_m, 0.3, 0.003);
    EXPECT_NEAR(std::abs(l.line.alpha_rad), kPi / 2, 0.2 * kPi / 180);
    EXPECT_GT(l.LengthM(), 1.0);
  }
}

TEST(LineExtractorNuisance, JointPartlyUnderAnOilStainIsFound) {
  const BevGrid grid(BevGridOptions{});
  const Tape stain{{1.55, 0.1}, {1.75, 0.1}, 0.16, 48.0};  // a stain 16 cm across on the joint
  const Tape joint{{0.6, 0.1}, {2.4, 0.1}, 0.01, 25.0};
  // The joint is drawn first: under the stain the floor is the stain's.
  const LineExtraction out = MakeExtractor(grid).Extract(RenderBev(grid, Paint({stain, joint})));
  ASSERT_EQ(CountLines(out, LinePolarity::kDark), 1);
  EXPECT_NEAR(out.lines[0].line.rho_m, 0.1, 0.003);
  EXPECT_GT(out.lines[0].LengthM(), 1.2);
}

}  // namespace
}  // namespace groundline::perception
