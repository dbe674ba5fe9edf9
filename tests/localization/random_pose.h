// A random SE(2) pose for the factor tests: x, y uniform in [-max_xy_m, max_xy_m],
// heading uniform in [-pi, pi).
#ifndef GROUNDLINE_TESTS_LOCALIZATION_RANDOM_POSE_H_
#define GROUNDLINE_TESTS_LOCALIZATION_RANDOM_POSE_H_

#include <numbers>
#include <random>

#include "groundline/core/se2.h"

namespace groundline::testing {

inline core::SE2 RandomPose(std::mt19937& rng, double max_xy_m = 5.0) {
  std::uniform_real_distribution<double> xy(-max_xy_m, max_xy_m);
  std::uniform_real_distribution<double> yaw(-std::numbers::pi, std::numbers::pi);
  // One draw per statement, in core::DrawVector's order.
  const double yaw_rad = yaw(rng);
  const double y_m = xy(rng);
  const double x_m = xy(rng);
  return core::SE2(x_m, y_m, yaw_rad);
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_LOCALIZATION_RANDOM_POSE_H_
