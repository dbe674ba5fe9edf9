// Orientation and type of extracted lines (line_classification.h).
#include "groundline/perception/line_classification.h"

#include <cassert>
#include <cmath>

namespace groundline::perception {

LineOrientation ClassifyOrientation(const HesseLine& line_base, double tolerance_rad) {
  // The direction is the normal turned by 90 deg: along x when the normal is along y.
  const double s = std::sin(tolerance_rad);
  if (std::abs(std::cos(line_base.alpha_rad)) <= s) return LineOrientation::kLongitudinal;
  if (std::abs(std::sin(line_base.alpha_rad)) <= s) return LineOrientation::kTransverse;
  return LineOrientation::kOblique;
}

int LineKindIndex(const LineKind& kind) {
  return 3 * (kind.polarity == LinePolarity::kDark ? 1 : 0) + static_cast<int>(kind.orientation);
}

LineKind LineKindOfIndex(int index) {
  assert(index >= 0 && index < kNumLineKinds);
  return {index >= 3 ? LinePolarity::kDark : LinePolarity::kBright,
          static_cast<LineOrientation>(index % 3)};
}

std::string_view LineKindName(const LineKind& kind) {
  static constexpr std::string_view kNames[kNumLineKinds] = {
      "tape_longitudinal",  "tape_transverse",  "tape_oblique",
      "joint_longitudinal", "joint_transverse", "joint_oblique"};
  return kNames[LineKindIndex(kind)];
}

}  // namespace groundline::perception
