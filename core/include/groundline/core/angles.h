// Angle unit conversions: one definition for every module.
#ifndef GROUNDLINE_CORE_ANGLES_H_
#define GROUNDLINE_CORE_ANGLES_H_

#include <numbers>

namespace groundline::core {

inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;
inline constexpr double kDegToRad = std::numbers::pi / 180.0;

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_ANGLES_H_
