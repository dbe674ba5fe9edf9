// Test points for the SE(2) suites: seeded random poses and tangent vectors,
// deliberately including angles at the small-angle series switch (1e-4 rad),
// far below it, and next to the +-pi wrap.
#ifndef GROUNDLINE_TESTS_CORE_SE2_TEST_POINTS_H_
#define GROUNDLINE_TESTS_CORE_SE2_TEST_POINTS_H_

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "groundline/core/random_draws.h"
#include "groundline/core/se2.h"
#include "test_units.h"

namespace groundline::core::testing {

using ::groundline::testing::kPi;
constexpr int kRandomTrials = 1000;
constexpr unsigned kSeed = 20240611;
constexpr unsigned kSeedOther = 7;  // a second, independent stream

// Angles that stress the implementation: exact zero, tiny, both sides of the
// series switch at 1e-4, and next to the wrap at +-pi.
inline std::vector<double> SpecialAngles() {
  const std::vector<double> magnitudes = {0.0,         1e-12,      1e-9,        1e-7,      1e-5,
                                          1e-4 - 1e-9, 1e-4,       1e-4 + 1e-9, 1e-3,      0.5,
                                          kPi / 2.0,   kPi - 1e-3, kPi - 1e-5,  kPi - 1e-9};
  std::vector<double> angles;
  for (double m : magnitudes) {
    angles.push_back(m);
    if (m != 0.0) angles.push_back(-m);
  }
  return angles;
}

// True if theta is within `margin` of the +-pi wrap. Vector-valued functions
// of a pose (Log, Minus) jump there by 2 pi, so central differences with a
// 1e-6 step must stay clear of it.
inline bool NearWrap(double theta_rad, double margin_rad = 5e-6) {
  return kPi - std::abs(theta_rad) < margin_rad;
}

// Tangent vectors: every special angle with a few translations, then
// kRandomTrials random ones (translation in [-5, 5] m, angle in (-pi, pi)).
inline std::vector<Vector3> TangentPoints(unsigned seed = kSeed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> trans(-5.0, 5.0);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  std::vector<Vector3> points;
  for (double theta : SpecialAngles()) {
    points.emplace_back(0.0, 0.0, theta);
    points.emplace_back(1.0, 0.0, theta);
    const Vector2 t = DrawVector<2>(trans, rng);
    points.emplace_back(t.x(), t.y(), theta);
  }
  for (int i = 0; i < kRandomTrials; ++i) {
    const double theta = angle(rng);  // one draw per statement, last first
    const Vector2 t = DrawVector<2>(trans, rng);
    points.emplace_back(t.x(), t.y(), theta);
  }
  return points;
}

// Poses: Exp of the tangent points (same coverage of angles).
inline std::vector<SE2> PosePoints(unsigned seed = kSeed) {
  std::vector<SE2> poses;
  for (const Vector3& xi : TangentPoints(seed)) poses.push_back(SE2(xi.x(), xi.y(), xi.z()));
  return poses;
}

// Max-abs difference of two matrices, for compact tolerance checks.
template <typename A, typename B>
double MaxAbsDiff(const A& a, const B& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

}  // namespace groundline::core::testing

#endif  // GROUNDLINE_TESTS_CORE_SE2_TEST_POINTS_H_
