// Line extraction on rendered BEV images (1 cm cells, the default grid):
// accuracy of a tape's centre line, one centre line for a wide bar,
// classification, merged dashes, junctions, and no lines from glare blobs or
// short scuff streaks.
#include "groundline/perception/line_extractor.h"

#include <gtest/gtest.h>

#include "rendered_bev.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace groundline::perception {
namespace {

TEST(LineExtractor, TapeCentreLineToTheMillimetre) {
  const BevGrid grid(BevGridOptions{});
  const LineExtractor extractor = MakeExtractor(grid);
  // A slightly slanted longitudinal tape 7.5 cm wide, centre 0.3137 m to the left.
  const HesseLine truth = NormalizeLine(0.3137, kPi / 2 - 0.02);
  const Eigen::Vector2d foot = truth.rho_m * truth.Normal();
  const Tape tape{foot - 2.6 * truth.Direction(), foot + 0.5 * truth.Direction(), 0.075, 170.0};
  const LineExtraction out = extractor.Extract(RenderBev(grid, Paint({tape})));
  ASSERT_EQ(out.lines.size(), 1u);
  const ExtractedLine& line = out.lines[0];
  const Eigen::Vector2d r = LineDifference(line.line, truth);
  EXPECT_LT(std::abs(r(0)), 0.002);
  EXPECT_LT(std::abs(r(1)), 0.1 * kPi / 180);
  EXPECT_EQ(line.kind, (LineKind{LinePolarity::kBright, LineOrientation::kLongitudinal}));
  EXPECT_GT(line.LengthM(), 1.2);
  EXPECT_GT(line.covariance(0, 0), 0.0);
}

TEST(LineExtractor, DarkJointAndWideStopBarAndJunction) {
  const BevGrid grid(BevGridOptions{});
  const LineExtractor extractor = MakeExtractor(grid);
  const Tape joint{{0.6, -0.25}, {2.4, -0.25}, 0.01, 25.0};    // longitudinal dark groove
  const Tape stop_bar{{1.6, -0.25}, {1.6, 0.8}, 0.20, 200.0};  // transverse, 20 cm wide
  const LineExtraction out = extractor.Extract(RenderBev(grid, Paint({stop_bar, joint})));
  int joints = 0, bars = 0;
  for (const ExtractedLine& l : out.lines) {
    if (l.kind == LineKind{LinePolarity::kDark, LineOrientation::kLongitudinal}) {
      ++joints;
      EXPECT_NEAR(l.line.rho_m, 0.25, 0.003);
    } else if (l.kind == LineKind{LinePolarity::kBright, LineOrientation::kTransverse}) {
      ++bars;
      EXPECT_TRUE(l.from_bar_edges);
      EXPECT_NEAR(l.line.rho_m, 1.6, 0.003);
    } else {
      ADD_FAILURE() << "unexpected line " << LineKindName(l.kind) << " rho " << l.line.rho_m
                    << " alpha " << l.line.alpha_rad;
    }
  }
  EXPECT_EQ(joints, 1);
  EXPECT_EQ(bars, 1);
  ASSERT_EQ(out.junctions.size(), 1u);
  EXPECT_NEAR(out.junctions[0].point_m.x(), 1.6, 0.005);
  EXPECT_NEAR(out.junctions[0].point_m.y(), -0.25, 0.005);
  EXPECT_EQ(out.junctions[0].shape, JunctionShape::kT);
}

TEST(LineExtractor, DashesMergeIntoOneLine) {
  const BevGrid grid(BevGridOptions{});
  const LineExtractor extractor = MakeExtractor(grid);
  std::vector<Tape> dashes;
  for (double x = 0.5; x < 2.5; x += 0.6) dashes.push_back({{x, 0.1}, {x + 0.3, 0.1}, 0.1, 180.0});
  const LineExtraction out = extractor.Extract(RenderBev(grid, Paint(dashes)));
  ASSERT_EQ(out.lines.size(), 1u);
  EXPECT_NEAR(out.lines[0].line.rho_m, 0.1, 0.003);
  EXPECT_GT(out.lines[0].LengthM(), 0.9);
}

TEST(LineExtractor, GlareBlobsAndShortScuffsGiveNoLines) {
  const BevGrid grid(BevGridOptions{});
  const LineExtractor extractor = MakeExtractor(grid);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(1.0, 2.2), y(-0.5, 0.5), angle(0.0, kPi);
  std::vector<Tape> scuffs;
  for (int i = 0; i < 12; ++i) {        // short dark streaks, 3 cm wide, 8 cm long
    const double heading = angle(rng);  // one draw per statement
    const double c_y = y(rng);
    const Eigen::Vector2d c(x(rng), c_y);
    const Eigen::Vector2d d(std::cos(heading), std::sin(heading));
    scuffs.push_back({c - 0.04 * d, c + 0.04 * d, 0.03, 60.0});
  }
  const Floor painted = Paint(scuffs);
  const Floor floor = [&](const Eigen::Vector2d& p) {
    double v = painted(p);
    for (const Eigen::Vector2d& g : {Eigen::Vector2d(1.5, 0.2), Eigen::Vector2d(2.0, -0.4)}) {
      v += 110.0 * std::exp(-0.5 * (p - g).squaredNorm() / (0.12 * 0.12));  // glare
    }
    v += 60.0 * std::exp(-0.5 * (p - Eigen::Vector2d(1.2, -0.2)).squaredNorm() / (0.03 * 0.03));
    return v;
  };
  const LineExtraction out = extractor.Extract(RenderBev(grid, floor));
  for (const ExtractedLine& l : out.lines) {
    ADD_FAILURE() << "line from glare or scuffs: " << LineKindName(l.kind) << " rho "
                  << l.line.rho_m << " alpha " << l.line.alpha_rad << " length " << l.LengthM();
  }
}

// A 50 cm crosswalk stripe whose outer edge lies beyond the seen floor: its
// one visible edge is a line, at the edge (not 3-4 cm inside, where the
// one-sided ridge peaks).
TEST(LineExtractor, HalfVisibleStripeYieldsItsEdge) {
  const BevGrid grid(BevGridOptions{});
  const LineExtractor extractor = MakeExtractor(grid);
  for (const double slope : {0.0, 0.02}) {
    // Inner edge 0.6 m to the right, the stripe out to 1.1 m (beyond the grid).
    const Eigen::Vector2d d(std::cos(slope), std::sin(slope)), left(-d.y(), d.x());
    const HesseLine edge = NormalizeLine(0.6, slope - kPi / 2);
    const Eigen::Vector2d c = -0.85 * left;
    const Tape stripe{c - 3.0 * d, c + 3.0 * d, 0.5, 200.0};
    const LineExtraction out = extractor.Extract(RenderBev(grid, Paint({stripe})));
    ASSERT_EQ(out.lines.size(), 1u) << "slope " << slope;
    const ExtractedLine& line = out.lines[0];
    EXPECT_TRUE(line.single_bar_edge);
    EXPECT_FALSE(line.from_bar_edges);
    const Eigen::Vector2d r = LineDifference(line.line, edge);
    EXPECT_LT(std::abs(r(0)), 0.003) << "slope " << slope;
    EXPECT_LT(std::abs(r(1)), 0.1 * kPi / 180) << "slope " << slope;
    EXPECT_GT(line.LengthM(), 1.2);
  }
}

// NEES of the measured-noise covariance over a small Monte Carlo: tapes of
// random offset, angle, contrast and noise; without a floor (the synthetic BEV
// has no errors constant along a line) and with the ridge filter's own
// correlation length (the synthetic BEV has no camera blur before it), the
// NEES follows chi-square(2).
TEST(LineExtractor, CovarianceIsConsistentOverMonteCarlo) {
  const BevGrid grid(BevGridOptions{});
  LineExtractorOptions options;
  options.rho_floor_m = 0.0;
  options.alpha_floor_rad = 0.0;
  options.min_sigma_px = 0.01;
  options.correlation_samples = 2.0 * std::sqrt(kPi) * options.ridge.sigma_cells;
  options.scatter_correlation_samples = options.correlation_samples;  // white noise: one length
  const LineExtractor extractor = MakeExtractor(grid, options);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> rho(0.1, 0.6), angle(-0.06, 0.06), grey(110.0, 200.0),
      noise(1.0, 4.0);
  std::vector<double> nees;
  for (unsigned trial = 0; trial < 40; ++trial) {
    const double alpha = kPi / 2 + angle(rng);  // one draw per statement, last first
    const HesseLine truth = NormalizeLine(rho(rng), alpha);
    const Eigen::Vector2d foot = truth.rho_m * truth.Normal();
    const Tape tape{foot - 2.6 * truth.Direction(), foot + 0.5 * truth.Direction(), 0.05,
                    grey(rng)};
    const LineExtraction out =
        extractor.Extract(RenderBev(grid, Paint({tape}), noise(rng), 100 + trial));
    ASSERT_EQ(out.lines.size(), 1u) << trial;
    const Eigen::Vector2d r = LineDifference(out.lines[0].line, truth);
    nees.push_back(r.dot(out.lines[0].covariance.inverse() * r));
  }
  const auto inside =
      std::count_if(nees.begin(), nees.end(), [](double e) { return e >= 0.0506 && e <= 7.378; });
  std::sort(nees.begin(), nees.end());
  EXPECT_GE(inside, 34);                  // >= 85 % (95 % expected)
  EXPECT_GT(nees[nees.size() / 2], 0.5);  // chi-square(2) median: 1.39
  EXPECT_LT(nees[nees.size() / 2], 3.0);
}

}  // namespace
}  // namespace groundline::perception

namespace groundline::perception {
namespace {

// A map of the calibration's floor uncertainty, sigma_m per axis in every cell.
std::shared_ptr<const calibration::BevUncertaintyMap> UniformMap(double sigma_m) {
  auto map = std::make_shared<calibration::BevUncertaintyMap>();
  map->x0_m = 0.0;
  map->y0_m = -2.0;
  map->cell_m = 0.2;
  map->cells_x = 20;
  map->cells_y = 20;
  map->covariance_m2.assign(400, sigma_m * sigma_m * Eigen::Matrix2d::Identity());
  return map;
}

double MinEigen(const Eigen::Matrix2d& m) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(m).eigenvalues().minCoeff();
}

// The calibration floor: a line is known no better than the line through its
// endpoints with the calibration's covariance there, and no worse than it
// was where the calibration is better than the ridge fit.
TEST(LineExtractor, CalibrationFloorBoundsTheLineCovarianceFromBelow) {
  const BevGrid grid(BevGridOptions{});
  const HesseLine truth = NormalizeLine(0.3137, kPi / 2 - 0.02);
  const Eigen::Vector2d foot = truth.rho_m * truth.Normal();
  const Tape tape{foot - 2.6 * truth.Direction(), foot + 0.5 * truth.Direction(), 0.075, 170.0};
  const Tape bar{{1.6, -0.6}, {1.6, 0.6}, 0.05, 170.0};
  const cv::Mat bev = RenderBev(grid, Paint({tape, bar}));
  const LineExtraction plain = MakeExtractor(grid).Extract(bev);
  ASSERT_EQ(plain.lines.size(), 2u);
  ASSERT_EQ(plain.junctions.size(), 1u);

  LineExtractorOptions options;
  options.calibration_floor = UniformMap(0.005);
  const LineExtraction floored = MakeExtractor(grid, options).Extract(bev);
  ASSERT_EQ(floored.lines.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const ExtractedLine& a = plain.lines[i];
    const ExtractedLine& b = floored.lines[i];
    EXPECT_EQ(a.line.rho_m, b.line.rho_m);  // the estimate itself does not change
    const LineEstimate calib = LineFromEndpoints(b.start_m, 2.5e-5 * Eigen::Matrix2d::Identity(),
                                                 b.end_m, 2.5e-5 * Eigen::Matrix2d::Identity())
                                   .value();
    const Eigen::Matrix2d floor = CovarianceInDescriptionOf(calib.line, b.line, calib.covariance);
    EXPECT_GE(MinEigen(b.covariance - floor), -1e-12) << i;
    EXPECT_GE(MinEigen(b.covariance - a.covariance), -1e-12) << i;
    // 5 mm at each end is far above what the ridge fit says (sub-millimetre).
    EXPECT_GT(std::sqrt(b.covariance(0, 0)), 0.003) << i;
    std::printf("line %zu: sigma rho %.2f -> %.2f mm\n", i, 1e3 * std::sqrt(a.covariance(0, 0)),
                1e3 * std::sqrt(b.covariance(0, 0)));
  }
  ASSERT_EQ(floored.junctions.size(), 1u);
  EXPECT_GT(floored.junctions[0].covariance.trace(), 10.0 * plain.junctions[0].covariance.trace());

  // A calibration far better than the fit changes nothing.
  options.calibration_floor = UniformMap(1e-7);
  const LineExtraction fine = MakeExtractor(grid, options).Extract(bev);
  ASSERT_EQ(fine.lines.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_LT((fine.lines[i].covariance - plain.lines[i].covariance).norm(),
              1e-9 * plain.lines[i].covariance.norm());
  }
  // A map that does not know where the line is leaves it as it was.
  auto unknown = std::make_shared<calibration::BevUncertaintyMap>(*UniformMap(0.005));
  unknown->covariance_m2.assign(400, Eigen::Matrix2d::Constant(std::nan("")));
  options.calibration_floor = unknown;
  const LineExtraction none = MakeExtractor(grid, options).Extract(bev);
  ASSERT_EQ(none.lines.size(), 2u);
  EXPECT_EQ(none.lines[0].covariance, plain.lines[0].covariance);
}

// The extraction of a frame does not depend on the scratch buffers' earlier
// contents, and a second frame of the same size allocates none of them anew.
TEST(LineExtractor, ScratchBuffersAreReusedAndLeaveTheResultUnchanged) {
  const BevGrid grid(BevGridOptions{});
  const LineExtractor extractor = MakeExtractor(grid);
  const cv::Mat a = RenderBev(grid, Paint({Tape{{0.6, -0.25}, {2.4, -0.25}, 0.01, 25.0},
                                           Tape{{1.6, -0.25}, {1.6, 0.8}, 0.20, 200.0}}));
  const cv::Mat b = RenderBev(grid, Paint({Tape{{0.4, 0.3}, {2.6, 0.35}, 0.075, 170.0}}));
  const LineExtraction fresh_a = extractor.Extract(a);
  const LineExtraction fresh_b = extractor.Extract(b);
  ASSERT_EQ(fresh_a.lines.size(), 2u);
  ASSERT_EQ(fresh_b.lines.size(), 1u);
  auto expect_same = [](const LineExtraction& got, const LineExtraction& want) {
    ASSERT_EQ(got.lines.size(), want.lines.size());
    for (std::size_t i = 0; i < got.lines.size(); ++i) {
      EXPECT_EQ(got.lines[i].line.rho_m, want.lines[i].line.rho_m) << i;
      EXPECT_EQ(got.lines[i].line.alpha_rad, want.lines[i].line.alpha_rad) << i;
      EXPECT_EQ(got.lines[i].covariance, want.lines[i].covariance) << i;
      EXPECT_EQ(got.lines[i].kind, want.lines[i].kind) << i;
    }
    ASSERT_EQ(got.junctions.size(), want.junctions.size());
    for (std::size_t i = 0; i < got.junctions.size(); ++i) {
      EXPECT_EQ(got.junctions[i].point_m, want.junctions[i].point_m) << i;
    }
    EXPECT_EQ(got.bright_threshold, want.bright_threshold);
    EXPECT_EQ(got.dark_threshold, want.dark_threshold);
  };
  ExtractionScratch scratch;
  expect_same(extractor.Extract(a, &scratch), fresh_a);
  const std::vector<const cv::Mat*> buffers = {&scratch.bev_float,
                                               &scratch.hessian.uu,
                                               &scratch.hessian.uv,
                                               &scratch.hessian.vv,
                                               &scratch.ridges.bright,
                                               &scratch.ridges.dark,
                                               &scratch.ridges.normal_rad,
                                               &scratch.ridges.eigen_ratio,
                                               &scratch.ridge.mean,
                                               &scratch.ridge.radius,
                                               &scratch.centres};
  std::vector<const std::uint8_t*> before;
  for (const cv::Mat* m : buffers) {
    ASSERT_FALSE(m->empty());
    before.push_back(m->data);
  }
  expect_same(extractor.Extract(b, &scratch), fresh_b);
  for (std::size_t i = 0; i < buffers.size(); ++i) EXPECT_EQ(buffers[i]->data, before[i]) << i;
  expect_same(extractor.Extract(a, &scratch), fresh_a);
}

// Each out-of-range option is reported by its name.
TEST(LineExtractor, OptionErrorsNameTheField) {
  EXPECT_TRUE(LineExtractorOptions{}.Validate().ok());
  struct Case {
    const char* field;
    std::function<void(LineExtractorOptions&)> spoil;
  };
  const std::vector<Case> cases = {
      {"reference_floor_grey", [](LineExtractorOptions& o) { o.reference_floor_grey = -1.0; }},
      {"reference_floor_grey", [](LineExtractorOptions& o) { o.reference_floor_grey = 300.0; }},
      {"dark_arc_max_radius_m", [](LineExtractorOptions& o) { o.dark_arc_max_radius_m = -1.0; }},
      {"dark_sagitta_significance",
       [](LineExtractorOptions& o) { o.dark_sagitta_significance = std::nan(""); }},
      {"dark_short_max_rms_m", [](LineExtractorOptions& o) { o.dark_short_max_rms_m = 0.0; }},
      {"min_bright_side_ratio", [](LineExtractorOptions& o) { o.min_bright_side_ratio = 1.5; }},
      {"bright_side_min_grey_share",
       [](LineExtractorOptions& o) { o.bright_side_min_grey_share = -0.1; }},
  };
  for (const Case& c : cases) {
    LineExtractorOptions o;
    c.spoil(o);
    const core::Status s = o.Validate();
    EXPECT_FALSE(s.ok()) << c.field;
    EXPECT_NE(s.message().find(c.field), std::string::npos) << s.message();
  }
}

}  // namespace
}  // namespace groundline::perception
