// Angle units shared by the tests (one definition, so that test files can be
// compiled together in unity batches).
#ifndef GROUNDLINE_TESTS_SUPPORT_TEST_UNITS_H_
#define GROUNDLINE_TESTS_SUPPORT_TEST_UNITS_H_

#include <numbers>

namespace groundline::testing {

inline constexpr double kPi = std::numbers::pi;
// One degree in radians.
inline constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_SUPPORT_TEST_UNITS_H_
