#include "groundline/sim/world.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace groundline::sim {

OrientedBox OrientedBox::FromMinMax(const Vector2& min_m, const Vector2& max_m) {
  assert(min_m.x() <= max_m.x() && min_m.y() <= max_m.y());
  OrientedBox box;
  box.center_m = 0.5 * (min_m + max_m);
  box.half_extent_m = 0.5 * (max_m - min_m);
  return box;
}

OrientedBox OrientedBox::AlongSegment(const Vector2& a_m, const Vector2& b_m, double thickness_m) {
  const Vector2 d = b_m - a_m;
  assert(d.norm() > 0.0 && thickness_m > 0.0);
  OrientedBox box;
  box.center_m = 0.5 * (a_m + b_m);
  box.half_extent_m = Vector2(0.5 * d.norm(), 0.5 * thickness_m);
  box.yaw_rad = std::atan2(d.y(), d.x());
  return box;
}

std::array<Vector2, 4> OrientedBox::Corners() const {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  const Vector2 ax = half_extent_m.x() * Vector2(c, s);
  const Vector2 ay = half_extent_m.y() * Vector2(-s, c);
  return {center_m - ax - ay, center_m + ax - ay, center_m + ax + ay, center_m - ax + ay};
}

bool OrientedBox::Contains(const Vector2& point_m) const {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  const Vector2 d = point_m - center_m;
  const double u = c * d.x() + s * d.y();
  const double v = -s * d.x() + c * d.y();
  return std::abs(u) <= half_extent_m.x() && std::abs(v) <= half_extent_m.y();
}

const char* ObstacleKindName(ObstacleKind kind) {
  switch (kind) {
    case ObstacleKind::kWall:
      return "wall";
    case ObstacleKind::kColumn:
      return "column";
    case ObstacleKind::kRackUpright:
      return "rack_upright";
    case ObstacleKind::kRackBeam:
      return "rack_beam";
    case ObstacleKind::kPallet:
      return "pallet";
    case ObstacleKind::kDockDoor:
      return "dock_door";
    case ObstacleKind::kTrailer:
      return "trailer";
  }
  return "unknown";
}

const char* MarkingColourName(MarkingColour colour) {
  switch (colour) {
    case MarkingColour::kYellow:
      return "yellow";
    case MarkingColour::kWhite:
      return "white";
    case MarkingColour::kRed:
      return "red";
    case MarkingColour::kBlue:
      return "blue";
    case MarkingColour::kGroove:
      return "groove";
  }
  return "unknown";
}

std::array<int, 3> MarkingColourRgb(MarkingColour colour) {
  switch (colour) {
    case MarkingColour::kYellow:
      return {245, 205, 0};
    case MarkingColour::kWhite:
      return {252, 252, 252};
    case MarkingColour::kRed:
      return {215, 40, 40};
    case MarkingColour::kBlue:
      return {30, 110, 200};
    case MarkingColour::kGroove:
      return {60, 60, 60};
  }
  return {0, 0, 0};
}

double PolylineLength(const std::vector<Vector2>& polyline_m) {
  double length_m = 0.0;
  for (std::size_t i = 1; i < polyline_m.size(); ++i) {
    length_m += (polyline_m[i] - polyline_m[i - 1]).norm();
  }
  return length_m;
}

core::SE2 MovingObstacle::PoseAt(double stamp_s) const {
  if (trajectory) return InterpolatePose(*trajectory, stamp_s);
  assert(path_m.size() >= 2);
  const double length_m = PolylineLength(path_m);
  assert(length_m > 0.0);
  double s = std::fmod(phase_m + speed_mps * stamp_s, 2.0 * length_m);
  if (s < 0.0) s += 2.0 * length_m;
  const bool returning = s > length_m;
  if (returning) s = 2.0 * length_m - s;
  std::size_t i = 1;
  double start_m = 0.0;
  for (; i + 1 < path_m.size(); ++i) {
    const double seg_m = (path_m[i] - path_m[i - 1]).norm();
    if (start_m + seg_m >= s) break;
    start_m += seg_m;
  }
  const Vector2 a = path_m[i - 1];
  const Vector2 b = path_m[i];
  const double seg_m = (b - a).norm();
  const double u = seg_m > 0.0 ? std::clamp((s - start_m) / seg_m, 0.0, 1.0) : 0.0;
  double yaw_rad = std::atan2(b.y() - a.y(), b.x() - a.x());
  if (returning) yaw_rad += std::numbers::pi;
  return core::SE2(a + u * (b - a), yaw_rad);
}

OrientedBox MovingObstacle::FootprintAt(double stamp_s) const {
  const core::SE2 pose = PoseAt(stamp_s);
  OrientedBox box;
  box.center_m = pose.translation();
  box.yaw_rad = pose.yaw();
  box.half_extent_m = IsCircle() ? Vector2(radius_m, radius_m) : half_extent_m;
  return box;
}

}  // namespace groundline::sim
