// What an extracted line is, where the evidence allows: its orientation to
// the vehicle (longitudinal, along base x: aisle and lane tape; transverse,
// along base y: stop bars, crosswalk stripes seen across, joints across the
// aisle; oblique otherwise) and its type from its polarity (bright: tape or
// paint; dark: a saw-cut joint or groove). Pure and thread-safe.
#ifndef GROUNDLINE_PERCEPTION_LINE_CLASSIFICATION_H_
#define GROUNDLINE_PERCEPTION_LINE_CLASSIFICATION_H_

#include <string_view>

#include "groundline/perception/hesse_line.h"

namespace groundline::perception {

enum class LinePolarity { kBright, kDark };
enum class LineOrientation { kLongitudinal, kTransverse, kOblique };

struct LineKind {
  LinePolarity polarity = LinePolarity::kBright;
  LineOrientation orientation = LineOrientation::kOblique;
  bool operator==(const LineKind&) const = default;
};

// Longitudinal when the line's direction is within tolerance_rad of base x,
// transverse when within tolerance_rad of base y, oblique otherwise.
LineOrientation ClassifyOrientation(const HesseLine& line_base, double tolerance_rad);

// "tape_longitudinal", "tape_transverse", "tape_oblique", "joint_longitudinal",
// "joint_transverse", "joint_oblique" (bright = tape, dark = joint).
std::string_view LineKindName(const LineKind& kind);

// All six kinds, in the order above (for per-kind summaries).
inline constexpr int kNumLineKinds = 6;
LineKind LineKindOfIndex(int index);
int LineKindIndex(const LineKind& kind);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_LINE_CLASSIFICATION_H_
