// Line extraction on floors the extractor was not tuned on, one nuisance at a
// time, on rendered BEV images of textured concrete: a straight hard shadow
// edge (a rack's, a pallet's, the vehicle's) is no line, while the one
// visible edge of a painted stripe on the same concrete is; a row of
// luminaire glare spots lined up along the aisle is no line.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "groundline/perception/line_extractor.h"
#include "rendered_bev.h"

namespace groundline::perception {
namespace {

// Concrete: grey 90 with a multiplicative texture of +-12 % (value noise at
// 4 cm and 1 cm, fixed by seed), as the floor's texture scales with the light.
double Texture(const Eigen::Vector2d& p, unsigned seed) {
  const auto hash = [seed](long i, long j) {
    std::uint32_t h = static_cast<std::uint32_t>(i * 73856093L ^ j * 19349663L ^ seed * 83492791L);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return (h & 0xffff) / 65535.0;
  };
  const auto noise = [&](double x, double y) {
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    const long i = static_cast<long>(fx), j = static_cast<long>(fy);
    const double a = hash(i, j), b = hash(i + 1, j), c = hash(i, j + 1), d = hash(i + 1, j + 1);
    return (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty;
  };
  return 1.0 + 0.16 * (noise(p.x() / 0.04, p.y() / 0.04) - 0.5) +
         0.08 * (noise(p.x() / 0.01, p.y() / 0.01) - 0.5);
}

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

// Glare: isotropic spots (sigma 4-6 cm, +100 grey levels, or +250 and
// saturated) of a row of luminaires reflected in a polished floor, lined up
// along the aisle 25-40 cm apart. (Rows so dense that the spots merge into a
// band, 20 cm apart at sigma 6-8 cm, are still taken for tape.)
TEST(LineExtractorGeneralization, RowOfGlareSpotsGivesNoLine) {
  const BevGrid grid(BevGridOptions{});
  for (const double spacing_m : {0.25, 0.4}) {
    for (const double sigma_m : {0.04, 0.06}) {
      for (const double peak : {100.0, 250.0}) {
        const Floor floor = [&](const Eigen::Vector2d& p) {
          double glare = 0.0;
          for (double x = 0.5; x < 2.6; x += spacing_m) {
            const double r2 = (p - Eigen::Vector2d(x, -0.35)).squaredNorm() / (sigma_m * sigma_m);
            glare += peak * std::exp(-0.5 * r2);
          }
          return 90.0 * Texture(p, 5) + glare;
        };
        SCOPED_TRACE("spacing " + std::to_string(spacing_m) + " sigma " + std::to_string(sigma_m) +
                     " peak " + std::to_string(peak));
        ExpectNoLines(MakeExtractor(grid).Extract(RenderBev(grid, floor)), "a row of glare");
      }
    }
  }
}

}  // namespace
}  // namespace groundline::perception
