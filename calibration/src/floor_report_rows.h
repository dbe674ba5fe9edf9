// The mount rows of the floor report (JSON and HTML): SI values turned into
// the units a technician checks, mm and degrees.
#ifndef GROUNDLINE_CALIBRATION_SRC_FLOOR_REPORT_ROWS_H_
#define GROUNDLINE_CALIBRATION_SRC_FLOOR_REPORT_ROWS_H_

#include <array>
#include <numbers>
#include <string>

#include "groundline/calibration/floor_calibration.h"

namespace groundline::calibration::internal {

struct MountRow {
  const char* key;
  const char* label;
  double scale;  // SI -> technician unit
  const char* unit;
};
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;
inline constexpr std::array<MountRow, 6> kMountRows = {{
    {"height_mm", "height", 1000.0, "mm"},
    {"pitch_deg", "pitch", kRadToDeg, "deg"},
    {"roll_deg", "roll", kRadToDeg, "deg"},
    {"yaw_deg", "yaw", kRadToDeg, "deg"},
    {"forward_mm", "forward offset", 1000.0, "mm"},
    {"lateral_mm", "lateral offset", 1000.0, "mm"},
}};

inline std::array<double, 6> MountValues(const CameraMount& m) {
  return {m.height_m, m.pitch_rad, m.roll_rad, m.yaw_rad, m.forward_m, m.lateral_m};
}

// Where the covariance scale came from, in words.
inline std::string CovarianceScaleText(const FloorCalibration& c,
                                       const FloorCalibrationOptions& options) {
  std::string text = options.solver.corner_sigma_px > 0.0 ? "stated corner noise"
                     : c.solution.sigma_px > c.solution.a_posteriori_sigma_px
                         ? "corner-noise floor (min_corner_sigma_px)"
                         : "a posteriori residual variance";
  if (c.solution.survey_sigma_m > 0.0) {
    text += " plus the layout's survey error of " +
            std::to_string(1000.0 * c.solution.survey_sigma_m).substr(0, 5) + " mm per corner";
  }
  return text;
}

}  // namespace groundline::calibration::internal

#endif  // GROUNDLINE_CALIBRATION_SRC_FLOOR_REPORT_ROWS_H_
