// Distance from a point to a segment in the plane.
#ifndef GROUNDLINE_CORE_SEGMENT_DISTANCE_H_
#define GROUNDLINE_CORE_SEGMENT_DISTANCE_H_

#include <Eigen/Core>
#include <algorithm>

namespace groundline::core {

// |p - q| for the point q of segment a-b nearest p; |p - a| when a == b.
inline double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_SEGMENT_DISTANCE_H_
