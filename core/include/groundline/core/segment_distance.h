// Distances between points and segments in the plane.
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

// The smallest distance between segments a0-a1 and b0-b1; 0 when they cross.
inline double SegmentSegmentDistance(const Eigen::Vector2d& a0, const Eigen::Vector2d& a1,
                                     const Eigen::Vector2d& b0, const Eigen::Vector2d& b1) {
  const auto cross = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    return p.x() * q.y() - p.y() * q.x();
  };
  const double d1 = cross(a1 - a0, b0 - a0), d2 = cross(a1 - a0, b1 - a0);
  const double d3 = cross(b1 - b0, a0 - b0), d4 = cross(b1 - b0, a1 - b0);
  if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0))) return 0.0;
  return std::min({DistanceToSegment(a0, b0, b1), DistanceToSegment(a1, b0, b1),
                   DistanceToSegment(b0, a0, a1), DistanceToSegment(b1, a0, a1)});
}

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_SEGMENT_DISTANCE_H_
