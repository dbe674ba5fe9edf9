// The zones of the imager's outer ring that the intrinsics report
// (calibration_report.h, border rule) and the live guidance
// (view_coverage.h) both count corners in, so that the two ask for the same.
#ifndef GROUNDLINE_CALIBRATION_SRC_IMAGER_ZONES_H_
#define GROUNDLINE_CALIBRATION_SRC_IMAGER_ZONES_H_

#include <Eigen/Core>

namespace groundline::calibration::internal {

// Zone names, in the order BorderZone numbers them.
inline constexpr const char* kBorderZoneNames[8] = {
    "top-left corner", "top edge",           "top-right corner", "left edge",
    "right edge",      "bottom-left corner", "bottom edge",      "bottom-right corner"};

// Zone (0..7) of pixel q in the outer ring `fraction` of the width and height
// deep of a w x h imager (pixel centres at integers), or -1 inside the ring.
inline int BorderZone(const Eigen::Vector2d& q, int w, int h, double fraction) {
  const double bx = fraction * w, by = fraction * h;
  const int col = q.x() < bx - 0.5 ? 0 : (q.x() > w - 0.5 - bx ? 2 : 1);
  const int row = q.y() < by - 0.5 ? 0 : (q.y() > h - 0.5 - by ? 2 : 1);
  if (row == 1 && col == 1) return -1;
  if (row == 0) return col;
  if (row == 1) return col == 0 ? 3 : 4;
  return 5 + col;
}

}  // namespace groundline::calibration::internal

#endif  // GROUNDLINE_CALIBRATION_SRC_IMAGER_ZONES_H_
