// Test support: synthetic BEV images of painted floors (1 cm cells, the
// default grid) and an extractor on an ideal all-seen grid, for the line
// extractor tests.
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
inline cv::Mat RenderBev(const BevGrid& grid, const Floor& floor, double noise_dn = 1.5,
                         unsigned seed = 7) {
  cv::Mat bev(grid.rows(), grid.cols(), CV_8U);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_dn);
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      double sum = 0.0;
      for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
          sum += floor(grid.FloorPointOfCell({c + i / 3.0, r + j / 3.0}));
        }
      }
      bev.at<std::uint8_t>(r, c) = cv::saturate_cast<std::uint8_t>(sum / 9.0 + noise(rng));
    }
  }
  return bev;
}

// camera_foot_m: the camera's foot point (base_link), when a test needs it.
inline LineExtractor MakeExtractor(const BevGrid& grid,
                                   const LineExtractorOptions& options = LineExtractorOptions{},
                                   std::optional<Eigen::Vector2d> camera_foot_m = std::nullopt) {
  const cv::Mat valid(grid.rows(), grid.cols(), CV_8U, cv::Scalar(255));
  const cv::Mat J(grid.rows(), grid.cols(), CV_64FC4, cv::Scalar(0.002, 0.0, 0.0, 0.002));
  return LineExtractor(grid, valid, J, options, camera_foot_m);
}

struct Tape {
  Eigen::Vector2d a, b;
  double width_m;
  double grey;
};

inline Floor Paint(std::vector<Tape> tapes, double concrete = 80.0) {
  return [tapes, concrete](const Eigen::Vector2d& p) {
    for (const Tape& t : tapes) {
      if (core::DistanceToSegment(p, t.a, t.b) <= 0.5 * t.width_m) return t.grey;
    }
    return concrete;
  };
}

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
