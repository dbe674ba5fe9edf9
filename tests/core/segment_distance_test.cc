// Distances between points and segments, against the minimum over dense
// samples of the segments (a brute force that shares no code with them).
#include "groundline/core/segment_distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "groundline/core/random_draws.h"

namespace groundline::core {
namespace {

// The smallest distance between points sampled every 1/200 of each segment.
double SampledDistance(const Eigen::Vector2d& a0, const Eigen::Vector2d& a1,
                       const Eigen::Vector2d& b0, const Eigen::Vector2d& b1) {
  constexpr int kN = 200;
  double best = 1e300;
  for (int i = 0; i <= kN; ++i) {
    const Eigen::Vector2d p = a0 + (a1 - a0) * (static_cast<double>(i) / kN);
    for (int j = 0; j <= kN; ++j) {
      const Eigen::Vector2d q = b0 + (b1 - b0) * (static_cast<double>(j) / kN);
      best = std::min(best, (p - q).norm());
    }
  }
  return best;
}

TEST(SegmentDistance, PointToSegmentIsTheNearestPointsDistance) {
  const Eigen::Vector2d a(0.0, 0.0), b(2.0, 0.0);
  EXPECT_DOUBLE_EQ(DistanceToSegment({1.0, 0.5}, a, b), 0.5);             // beside it
  EXPECT_DOUBLE_EQ(DistanceToSegment({3.0, 0.0}, a, b), 1.0);             // beyond an end
  EXPECT_DOUBLE_EQ(DistanceToSegment({-3.0, 4.0}, a, b), 5.0);            // off the other end
  EXPECT_DOUBLE_EQ(DistanceToSegment({1.0, 1.0}, a, a), std::sqrt(2.0));  // a point
}

TEST(SegmentDistance, SegmentToSegmentMatchesDenseSampling) {
  EXPECT_EQ(SegmentSegmentDistance({0, 0}, {2, 2}, {0, 2}, {2, 0}), 0.0);         // crossing
  EXPECT_DOUBLE_EQ(SegmentSegmentDistance({0, 0}, {2, 0}, {0, 1}, {2, 1}), 1.0);  // parallel
  EXPECT_DOUBLE_EQ(SegmentSegmentDistance({0, 0}, {1, 0}, {2, 1}, {2, 3}), std::sqrt(2.0));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 40; ++k) {
    const Eigen::Vector2d a0 = DrawVector<2>(u, rng), a1 = DrawVector<2>(u, rng);
    const Eigen::Vector2d b0 = DrawVector<2>(u, rng), b1 = DrawVector<2>(u, rng);
    const double d = SegmentSegmentDistance(a0, a1, b0, b1);
    // Sampling overestimates by at most half a sample step of the longer.
    const double step = std::max((a1 - a0).norm(), (b1 - b0).norm()) / 200.0;
    const double sampled = SampledDistance(a0, a1, b0, b1);
    EXPECT_GE(d, 0.0);
    EXPECT_LE(d, sampled + 1e-12) << k;
    EXPECT_GE(d, sampled - step) << k;
    EXPECT_NEAR(d, SegmentSegmentDistance(b1, b0, a0, a1), 1e-12) << k;  // symmetric
  }
}

}  // namespace
}  // namespace groundline::core
