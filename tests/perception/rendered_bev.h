// Test support: synthetic BEV images of painted floors (1 cm cells, the
// default grid) and an extractor on an ideal all-seen grid, for the line
// extractor tests. The rendering is compiled optimized in its own library
// (rendered_bev.cc): the test code itself is built at -O0, where the
// supersampled painting of a Monte Carlo of BEVs took most of the tests' time.
#ifndef GROUNDLINE_TESTS_PERCEPTION_RENDERED_BEV_H_
#define GROUNDLINE_TESTS_PERCEPTION_RENDERED_BEV_H_

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "groundline/core/segment_distance.h"
#include "groundline/perception/line_extractor.h"
#include "test_units.h"

namespace groundline::perception {

using ::groundline::testing::kPi;

// A floor painter: reflectance (grey level) at a floor point in base_link.
using Floor = std::function<double(const Eigen::Vector2d&)>;

// The BEV of a floor, 3x3 supersampled per cell, plus Gaussian noise.
cv::Mat RenderBev(const BevGrid& grid, const Floor& floor, double noise_dn = 1.5,
                  unsigned seed = 7);

// camera_foot_m: the camera's foot point (base_link), when a test needs it.
LineExtractor MakeExtractor(const BevGrid& grid,
                            const LineExtractorOptions& options = LineExtractorOptions{},
                            std::optional<Eigen::Vector2d> camera_foot_m = std::nullopt);

struct Tape {
  Eigen::Vector2d a, b;
  double width_m;
  double grey;
};

// Tapes on plain concrete: the first tape that covers a point gives its grey.
Floor Paint(std::vector<Tape> tapes, double concrete = 80.0);

// Concrete: a multiplicative texture of +-12 % around 1 (value noise at 4 cm
// and 1 cm, fixed by seed), as the floor's texture scales with the light.
double Texture(const Eigen::Vector2d& p, unsigned seed);

// One failure per extracted line: `what` must give none.
inline void ExpectNoLines(const LineExtraction& out, const char* what) {
  for (const ExtractedLine& l : out.lines) {
    ADD_FAILURE() << "line from " << what << ": " << LineKindName(l.kind) << " rho " << l.line.rho_m
                  << " alpha " << l.line.alpha_rad << " length " << l.LengthM()
                  << (l.single_bar_edge ? " (single bar edge)" : "")
                  << (l.from_bar_edges ? " (bar)" : "");
  }
}

}  // namespace groundline::perception

#endif  // GROUNDLINE_TESTS_PERCEPTION_RENDERED_BEV_H_
