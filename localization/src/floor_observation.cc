#include "groundline/localization/floor_observation.h"

#include <algorithm>
#include <limits>

namespace groundline::localization {

double FloorView::InsideDistance(const Eigen::Vector2d& p_base_m) const {
  const size_t n = polygon_base_m.size();
  if (n < 3) return -std::numeric_limits<double>::infinity();
  double inside = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = polygon_base_m[i];
    const Eigen::Vector2d edge = polygon_base_m[(i + 1) % n] - a;
    const double length = edge.norm();
    if (!(length > 0.0)) continue;
    // Left of a counter-clockwise edge is inside.
    const Eigen::Vector2d d = p_base_m - a;
    inside = std::min(inside, (edge.x() * d.y() - edge.y() * d.x()) / length);
  }
  return inside;
}

}  // namespace groundline::localization
