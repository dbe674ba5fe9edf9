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

double FloorView::LengthInside(const Eigen::Vector2d& a_base_m, const Eigen::Vector2d& b_base_m,
                               double margin_m) const {
  const size_t n = polygon_base_m.size();
  if (n < 3) return 0.0;
  const Eigen::Vector2d d = b_base_m - a_base_m;
  double t_low = 0.0, t_high = 1.0;
  for (size_t i = 0; i < n && t_low < t_high; ++i) {
    const Eigen::Vector2d& v = polygon_base_m[i];
    const Eigen::Vector2d edge = polygon_base_m[(i + 1) % n] - v;
    const double length = edge.norm();
    if (!(length > 0.0)) continue;
    // Inside by margin_m: normal . (a + t d - v) >= margin_m, normal the
    // edge's inward (left) unit normal.
    const Eigen::Vector2d normal = Eigen::Vector2d(-edge.y(), edge.x()) / length;
    const double at_a = normal.dot(a_base_m - v) - margin_m;
    const double rate = normal.dot(d);
    if (rate == 0.0) {
      if (at_a < 0.0) return 0.0;
    } else if (rate > 0.0) {
      t_low = std::max(t_low, -at_a / rate);
    } else {
      t_high = std::min(t_high, -at_a / rate);
    }
  }
  return std::max(0.0, t_high - t_low) * d.norm();
}

}  // namespace groundline::localization
