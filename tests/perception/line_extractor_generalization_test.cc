// Line extraction on floors the extractor was not tuned on, one nuisance at a
// time, on rendered BEV images of textured concrete: a straight hard shadow
// edge (a rack's, a pallet's, the vehicle's) is no line, while the one
// visible edge of a painted stripe on the same concrete is; lit concrete
// between two shadows is no bar, while paint bars are; a row of luminaire
// glare spots lined up along the aisle, even merged into a band, is no line;
// the lit flank of a shadow beside a darker patch is no tape, while a tape
// beside a shadow's edge is; a faint joint on a dim floor is found.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "groundline/perception/line_extractor.h"
#include "rendered_bev.h"

namespace groundline::perception {
namespace {

struct ShadowCase {
  double factor;     // lux multiplier in the shadow
  double alpha_deg;  // the edge's direction from base x
  const char* what;
};

// A straight hard shadow edge through the view: the floor on one side lit,
// on the other in shadow (the same concrete, darker by `factor`).
TEST(LineExtractorGeneralization, StraightShadowEdgeGivesNoLine) {
  const BevGrid grid(BevGridOptions{});
  for (const ShadowCase& c : {ShadowCase{0.4, 0.0, "along the aisle, deep"},
                              ShadowCase{0.7, 0.0, "along the aisle, light"},
                              ShadowCase{0.5, 90.0, "across"}, ShadowCase{0.5, 30.0, "oblique"}}) {
    const Eigen::Vector2d d(std::cos(c.alpha_deg * kPi / 180), std::sin(c.alpha_deg * kPi / 180));
    const Eigen::Vector2d through(1.5, 0.2);
    const Floor floor = [&](const Eigen::Vector2d& p) {
      const double side = d.x() * (p - through).y() - d.y() * (p - through).x();
      return 90.0 * Texture(p, 3) * (side > 0.0 ? 1.0 : c.factor);
    };
    const cv::Mat bev = RenderBev(grid, floor);
    ExpectNoLines(MakeExtractor(grid).Extract(bev), c.what);
    if (c.alpha_deg == 30.0) {
      // It is the roughness test that rejects this one: a bar's edge otherwise.
      LineExtractorOptions options;
      options.single_edge_min_roughness_ratio = 0.0;
      EXPECT_EQ(MakeExtractor(grid, options).Extract(bev).lines.size(), 1u);
    }
  }
}

// The control: a 50 cm crosswalk stripe of smooth paint on the same textured
// concrete, its far edge out of view, still gives its one visible edge.
TEST(LineExtractorGeneralization, StripeEdgeOnTexturedConcreteIsFound) {
  const BevGrid grid(BevGridOptions{});
  for (const double alpha_deg : {0.0, 30.0}) {
    const Eigen::Vector2d d(std::cos(alpha_deg * kPi / 180), std::sin(alpha_deg * kPi / 180));
    const Eigen::Vector2d n(-d.y(), d.x());
    const Eigen::Vector2d edge(1.5, 0.6);
    const Floor floor = [&](const Eigen::Vector2d& p) {
      const double into = n.dot(p - edge);  // the stripe: 0..0.5 m beyond the edge
      return into > 0.0 && into < 0.5 ? 180.0 : 90.0 * Texture(p, 3);
    };
    const LineExtraction out = MakeExtractor(grid).Extract(RenderBev(grid, floor));
    ASSERT_EQ(out.lines.size(), 1u) << "stripe at " << alpha_deg << " deg";
    EXPECT_TRUE(out.lines[0].single_bar_edge);
    EXPECT_NEAR(std::abs(SignedDistance(out.lines[0].line, edge)), 0.0, 0.005);
  }
}

// The angle between a line and the ray from `foot` to its midpoint.
double RayAngleDeg(const ExtractedLine& line, const Eigen::Vector2d& foot) {
  const Eigen::Vector2d ray = 0.5 * (line.start_m + line.end_m) - foot;
  const Eigen::Vector2d along = line.end_m - line.start_m;
  return std::atan2(std::abs(ray.x() * along.y() - ray.y() * along.x()), std::abs(ray.dot(along))) *
         180.0 / kPi;
}

// A box standing beside the path, its smooth bright side facing the camera:
// the bird's-eye view smears its vertical edge along the ray from the
// camera's foot point, and a step from textured concrete to a smooth bright
// face is what a stripe's edge looks like. Only the ray tells them apart.
TEST(LineExtractorGeneralization, VerticalEdgeOfAStandingBoxGivesNoLine) {
  const BevGrid grid(BevGridOptions{});
  const Eigen::Vector2d foot(0.1, 0.0);     // the camera's foot point
  const Eigen::Vector2d corner(0.5, 0.12);  // the near corner, short of the view
  const Eigen::Vector2d ray = (corner - foot).normalized();
  const Floor floor = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d q = p - foot;
    const bool box = ray.x() * q.y() - ray.y() * q.x() > 0.0 && q.dot(ray) > (corner - foot).norm();
    return box ? 170.0 : 90.0 * Texture(p, 5);
  };
  const cv::Mat bev = RenderBev(grid, floor);
  ExpectNoLines(MakeExtractor(grid, {}, foot).Extract(bev), "box edge along the ray");
  // The control: seen from another foot point the same edge is no ray, and
  // it passes as a bar's edge; the ray test is what rejects it.
  const LineExtraction off = MakeExtractor(grid, {}, Eigen::Vector2d(0.1, -0.6)).Extract(bev);
  ASSERT_EQ(off.lines.size(), 1u);
  EXPECT_TRUE(off.lines[0].single_bar_edge);
  EXPECT_NEAR(std::abs(SignedDistance(off.lines[0].line, corner + 0.5 * ray)), 0.0, 0.005);
  LineExtractorOptions no_ray_test;
  no_ray_test.single_edge_max_radial_deg = 0.0;
  EXPECT_EQ(MakeExtractor(grid, no_ray_test, foot).Extract(bev).lines.size(), 1u);
}

// A thin post beside the path (a rack leg, a bollard): both its vertical
// edges lie on rays from the camera's foot point, so its streak in the
// bird's-eye view is a wedge that widens with the range. A tape on the same
// ray keeps its width and stays a line.
TEST(LineExtractorGeneralization, StreakOfAPostGivesNoLineButATapeOnTheSameRayIsFound) {
  const BevGrid grid(BevGridOptions{});
  const Eigen::Vector2d foot(0.1, 0.0);
  const Eigen::Vector2d base(1.0, 0.08);  // the post's foot on the floor
  const Eigen::Vector2d ray = (base - foot).normalized();
  const Eigen::Vector2d across(-ray.y(), ray.x());
  const double half_angle = 0.0125 / (base - foot).norm();  // 2.5 cm wide at its base
  const Floor post = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d q = p - foot;
    const double r = q.dot(ray);
    const bool on = r > (base - foot).norm() && std::abs(q.dot(across)) < half_angle * r;
    return on ? 175.0 : 90.0 * Texture(p, 7);
  };
  const cv::Mat bev = RenderBev(grid, post);
  ExpectNoLines(MakeExtractor(grid, {}, foot).Extract(bev), "post on a ray");
  // With the width test off the streak is a line: the test is what acts.
  LineExtractorOptions off;
  off.ray_line_max_width_growth = 0.0;
  const LineExtraction without = MakeExtractor(grid, off, foot).Extract(bev);
  ASSERT_EQ(without.lines.size(), 1u);
  EXPECT_LT(RayAngleDeg(without.lines[0], foot), 1.0);

  // A 5 cm tape along the same ray, from the near edge of the view out.
  const Floor tape = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d q = p - foot;
    return std::abs(q.dot(across)) < 0.025 ? 175.0 : 90.0 * Texture(p, 7);
  };
  const LineExtraction found = MakeExtractor(grid, {}, foot).Extract(RenderBev(grid, tape));
  ASSERT_EQ(found.lines.size(), 1u);
  EXPECT_NEAR(std::abs(SignedDistance(found.lines[0].line, base)), 0.0, 0.005);
}

// Lit concrete between two straight shadows (the gap between two racks'
// shadows) is bright between two dark sides, as a wide bar: its floor is as
// rough as the shadowed floor, relative to its grey, where paint is smooth.
TEST(LineExtractorGeneralization, LitGapBetweenTwoShadowsGivesNoLine) {
  const BevGrid grid(BevGridOptions{});
  for (const double width_m : {0.3, 0.5}) {
    for (const double alpha_deg : {0.0, 90.0}) {
      const Eigen::Vector2d d(std::cos(alpha_deg * kPi / 180), std::sin(alpha_deg * kPi / 180));
      const Eigen::Vector2d n(-d.y(), d.x());
      const Eigen::Vector2d centre(1.5, 0.1);
      const Floor floor = [&](const Eigen::Vector2d& p) {
        const bool lit = std::abs(n.dot(p - centre)) < 0.5 * width_m;
        return 90.0 * Texture(p, 7) * (lit ? 1.0 : 0.45);
      };
      const cv::Mat bev = RenderBev(grid, floor);
      const std::string what =
          "a lit gap " + std::to_string(width_m) + " m wide at " + std::to_string(alpha_deg);
      ExpectNoLines(MakeExtractor(grid).Extract(bev), what.c_str());
      if (width_m == 0.3 && alpha_deg == 0.0) {
        // It is the bar roughness test that rejects it: a bar otherwise.
        LineExtractorOptions options;
        options.bar_min_roughness_ratio = 0.0;
        const LineExtraction out = MakeExtractor(grid, options).Extract(bev);
        ASSERT_EQ(out.lines.size(), 1u);
        EXPECT_TRUE(out.lines[0].from_bar_edges);
      }
    }
  }
}

// The control: smooth paint bars (a 30 cm stop bar, a 10 cm and a 5 cm tape)
// on the same textured concrete are still found, at their centre lines.
TEST(LineExtractorGeneralization, PaintBarsOnTexturedConcreteAreFound) {
  const BevGrid grid(BevGridOptions{});
  for (const double width_m : {0.05, 0.1, 0.3}) {
    const Eigen::Vector2d centre(1.5, -0.2);
    const Floor floor = [&](const Eigen::Vector2d& p) {
      return std::abs(p.x() - centre.x()) < 0.5 * width_m ? 170.0 : 90.0 * Texture(p, 7);
    };
    const LineExtraction out = MakeExtractor(grid).Extract(RenderBev(grid, floor));
    ASSERT_EQ(out.lines.size(), 1u) << "bar " << width_m << " m";
    EXPECT_NEAR(std::abs(SignedDistance(out.lines[0].line, centre)), 0.0, 0.003);
  }
}

// Glare: isotropic spots (sigma 4-8 cm, +100 grey levels, or +250 and
// saturated) of a row of luminaires reflected in a polished floor, lined up
// along the aisle 10-40 cm apart; the densest rows merge into a continuous
// band, whose flanks are Gaussian where paint's fall within a cell or two.
TEST(LineExtractorGeneralization, RowOfGlareSpotsGivesNoLine) {
  const BevGrid grid(BevGridOptions{});
  for (const double spacing_m : {0.1, 0.2, 0.4}) {
    for (const double sigma_m : {0.04, 0.08}) {
      for (const double peak : {100.0, 250.0}) {
        const Floor floor = [&](const Eigen::Vector2d& p) {
          double glare = 0.0;
          // Beyond 6 sigma of the row a spot adds under 0.004 grey levels.
          if (std::abs(p.y() + 0.35) > 6.0 * sigma_m) return 90.0 * Texture(p, 5);
          for (double x = 0.5; x < 2.6; x += spacing_m) {
            const double r2 = (p - Eigen::Vector2d(x, -0.35)).squaredNorm() / (sigma_m * sigma_m);
            glare += peak * std::exp(-0.5 * r2);
          }
          return 90.0 * Texture(p, 5) + glare;
        };
        SCOPED_TRACE("spacing " + std::to_string(spacing_m) + " sigma " + std::to_string(sigma_m) +
                     " peak " + std::to_string(peak));
        const cv::Mat bev = RenderBev(grid, floor);
        ExpectNoLines(MakeExtractor(grid).Extract(bev), "a row of glare");
        if (spacing_m == 0.2 && sigma_m == 0.08 && peak == 250.0) {
          // It is the flank test that rejects this band: a line otherwise.
          LineExtractorOptions options;
          options.min_flank_sharpness = 0.0;
          EXPECT_GE(MakeExtractor(grid, options).Extract(bev).lines.size(), 1u);
        }
      }
    }
  }
}

// A strip of lit floor between a shadow and a slightly darker patch (wet or
// worn concrete): bright against both sides, as a tape, but much brighter
// than one side only, and its other side is the same floor a few percent off.
// It is taken as an edge, and as an edge it is a shadow's (the roughness
// test).
TEST(LineExtractorGeneralization, LitFlankBesideADarkerPatchGivesNoLine) {
  const BevGrid grid(BevGridOptions{});
  for (const double alpha_deg : {0.0, 90.0}) {
    for (const double strip_m : {0.05, 0.08}) {
      const Eigen::Vector2d d(std::cos(alpha_deg * kPi / 180), std::sin(alpha_deg * kPi / 180));
      const Eigen::Vector2d n(-d.y(), d.x());
      const Eigen::Vector2d edge(1.5, 0.1);
      const Floor floor = [&](const Eigen::Vector2d& p) {
        const double across = n.dot(p - edge);
        const double light = across > 0.0 ? 0.4 : across > -strip_m ? 1.0 : 0.9;
        return 90.0 * Texture(p, 11) * light;
      };
      const cv::Mat bev = RenderBev(grid, floor);
      const std::string what = "a lit flank " + std::to_string(strip_m) + " m wide at " +
                               std::to_string(alpha_deg) + " deg";
      ExpectNoLines(MakeExtractor(grid).Extract(bev), what.c_str());
      if (strip_m == 0.05 && alpha_deg == 0.0) {
        // It is the side test that rejects it: a tape line otherwise.
        LineExtractorOptions options;
        options.min_bright_side_ratio = 0.0;
        options.bright_side_min_grey_share = 0.0;
        const LineExtraction out = MakeExtractor(grid, options).Extract(bev);
        ASSERT_EQ(out.lines.size(), 1u);
        EXPECT_FALSE(out.lines[0].from_bar_edges || out.lines[0].single_bar_edge);
      }
    }
  }
}

// The control: a narrow tape with a shadow's edge 5 cm beside it, so that
// one side is the shadowed floor and the other the lit floor, is still a
// line (its lit side is darker than the paint by much more than a few
// percent of its grey).
TEST(LineExtractorGeneralization, TapeBesideAShadowEdgeIsFound) {
  const BevGrid grid(BevGridOptions{});
  const Floor floor = [&](const Eigen::Vector2d& p) {
    if (std::abs(p.y() - 0.2) < 0.025) return 170.0;
    return 90.0 * Texture(p, 13) * (p.y() > 0.275 ? 0.4 : 1.0);
  };
  const LineExtraction out = MakeExtractor(grid).Extract(RenderBev(grid, floor));
  ASSERT_EQ(out.lines.size(), 1u);
  EXPECT_EQ(out.lines[0].kind.polarity, LinePolarity::kBright);
  // The shadow's step, within the ridge filter's reach, pulls the centre
  // toward it by about 5 mm.
  EXPECT_NEAR(out.lines[0].line.rho_m, 0.2, 0.007);
  EXPECT_GT(out.lines[0].LengthM(), 1.2);
}

// A saw-cut joint, 10 mm wide and 40 % darker than its floor, on concrete
// whose median grey is 30 (dim light, or an exposure set for a brighter
// floor): 12 grey levels deep, below the joints' grey-level thresholds,
// which are for a floor of the reference grey. The frame is scaled up to it
// first, and the joint is found as on a floor of grey 75.
TEST(LineExtractorGeneralization, JointOnADimFloorIsFound) {
  const BevGrid grid(BevGridOptions{});
  for (const double alpha_deg : {0.0, 90.0}) {
    const Eigen::Vector2d d(std::cos(alpha_deg * kPi / 180), std::sin(alpha_deg * kPi / 180));
    const Eigen::Vector2d n(-d.y(), d.x());
    const Eigen::Vector2d through(1.6, -0.1);
    const Floor floor = [&](const Eigen::Vector2d& p) {
      const bool joint = std::abs(n.dot(p - through)) < 0.006;
      return 30.0 * Texture(p, 17) * (joint ? 0.5 : 1.0);
    };
    const cv::Mat bev = RenderBev(grid, floor, 1.0);
    SCOPED_TRACE("joint at " + std::to_string(alpha_deg) + " deg");
    const LineExtraction out = MakeExtractor(grid).Extract(bev);
    ASSERT_EQ(out.lines.size(), 1u);
    EXPECT_EQ(out.lines[0].kind.polarity, LinePolarity::kDark);
    // The texture, +-12 % at 4 cm, moves a groove this faint by up to 5 mm
    // (0.2 mm on plain concrete; measured over four textures).
    EXPECT_NEAR(std::abs(out.lines[0].line.rho_m), std::abs(n.dot(through)), 0.006);
    EXPECT_GT(out.lines[0].LengthM(), 1.0);
    // Without the exposure's scaling the joint is too faint.
    LineExtractorOptions options;
    options.reference_floor_grey = 0.0;
    EXPECT_EQ(MakeExtractor(grid, options).Extract(bev).lines.size(), 0u);
  }
}

}  // namespace
}  // namespace groundline::perception
