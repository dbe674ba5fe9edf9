// The simulated warehouse: obstacles above the floor (what the planar LiDAR and
// the vehicle body can hit), floor markings (what the camera sees; the ground
// truth map), the zone's natural driving paths, and moving clutter.
//
// Frames and units: everything is in the map frame (x, y in metres, REP-103
// axes, z up from the floor). Obstacles are extruded rectangles: a footprint
// (an oriented box) between z_min_m and z_max_m above the floor. Whether the
// LiDAR sees an obstacle is decided by that height interval alone: a scan plane
// at height h hits the obstacle iff z_min_m <= h <= z_max_m. Rack beams, for
// example, start at 1.5 m and are invisible to a 0.18 m scan plane but still
// count for the vehicle's clearance.
//
// All types are plain values; a World is immutable once built and may be shared
// across threads.
#ifndef GROUNDLINE_SIM_WORLD_H_
#define GROUNDLINE_SIM_WORLD_H_

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "groundline/core/floor_map.h"
#include "groundline/core/se2.h"
#include "groundline/core/trajectory.h"
#include "groundline/core/trajectory_association.h"

namespace groundline::sim {

using core::Vector2;

// A rectangle of any orientation: centre, half extents along its own axes, and
// the yaw of its own x axis in the map frame.
struct OrientedBox {
  Vector2 center_m = Vector2::Zero();
  Vector2 half_extent_m = Vector2::Zero();
  double yaw_rad = 0.0;

  // The axis-aligned box [min_m, max_m].
  static OrientedBox FromMinMax(const Vector2& min_m, const Vector2& max_m);
  // A box of the given thickness centred on the segment a-b (a wall).
  static OrientedBox AlongSegment(const Vector2& a_m, const Vector2& b_m, double thickness_m);

  // The four corners, counter-clockwise.
  std::array<Vector2, 4> Corners() const;
  // True if the point is inside or on the boundary.
  bool Contains(const Vector2& point_m) const;
  // Radius of the circumscribed circle.
  double BoundingRadius() const { return half_extent_m.norm(); }
};

enum class ObstacleKind {
  kWall,         // building walls and solid blocks; full height
  kColumn,       // building columns; full height
  kRackUpright,  // steel rack uprights; full height, seen by the LiDAR
  kRackBeam,     // the stack of pallet beams above the first level; not seen by a low LiDAR
  kPallet,       // pallet loads and pallet stacks on the floor
  kDockDoor,     // closed roll-up dock doors
  kTrailer,      // the walls of a trailer docked at an open door
};

const char* ObstacleKindName(ObstacleKind kind);

struct Obstacle {
  ObstacleKind kind = ObstacleKind::kWall;
  OrientedBox box;
  double z_min_m = 0.0;
  double z_max_m = 10.0;
  // Diffuse reflectivity in [0, 1] for the LiDAR intensity.
  double reflectivity = 0.5;
  // Diffuse reflectance seen by the floor camera; < 0: one per kind
  // (floor_nuisances.h, StandingOccluders).
  double camera_reflectance = -1.0;

  bool IntersectsPlane(double height_m) const { return z_min_m <= height_m && height_m <= z_max_m; }
};

// Marking kinds and polarity are the dataset floor map's (core/floor_map.h).
using core::MarkingKind;
using core::MarkingPolarity;

enum class MarkingColour { kYellow, kWhite, kRed, kBlue, kGroove };

const char* MarkingColourName(MarkingColour colour);
// 8-bit sRGB of a colour as painted (a groove is dark grey).
std::array<int, 3> MarkingColourRgb(MarkingColour colour);

// One marking: a band of width_m centred on a polyline. A closed outline (a
// staging box) repeats its first point at the end. Dashed tape starts with a
// dash at the first point and alternates dash_length_m / gap_length_m along the
// polyline's arc length.
struct FloorMarking {
  MarkingKind kind = MarkingKind::kTapeSolid;
  MarkingPolarity polarity = MarkingPolarity::kBright;
  MarkingColour colour = MarkingColour::kYellow;
  std::vector<Vector2> polyline_m;
  double width_m = 0.075;
  double dash_length_m = 0.0;  // kTapeDashed only
  double gap_length_m = 0.0;   // kTapeDashed only
  // Fraction of the marking's area worn away in patches, for the renderer; the
  // marking stays in the ground-truth map whatever its wear.
  double wear_fraction = 0.0;
};

// The zone's natural driving paths: straight edges between nodes, undirected.
// Routes and moving obstacles follow them. `preference` biases the random walk
// of the route generator (zone B prefers aisles to cross-aisle hops).
struct RoadGraph {
  struct Edge {
    int from = 0;
    int to = 0;
    double preference = 1.0;
  };
  std::vector<Vector2> nodes_m;
  std::vector<Edge> edges;
};

enum class MovingKind { kForklift, kPedestrian, kRobot };

// A moving obstacle: a box (forklift) or a circle (a pedestrian's legs at
// LiDAR height) that goes back and forth along a polyline at constant speed.
// At stamp t it is at arc length s = (phase_m + speed_mps * t) folded into
// [0, L] ping-pong fashion, facing its direction of travel. Or, when
// `trajectory` is set (another robot of a fleet run), a box that follows that
// trajectory (T_map_obstacle, interpolated; parked at its first and last pose
// outside its time span); path_m, speed and phase are then unused.
struct MovingObstacle {
  MovingKind kind = MovingKind::kForklift;
  Vector2 half_extent_m = Vector2(1.2, 0.6);  // boxes: along / across travel
  double radius_m = 0.0;                      // > 0 makes it a circle
  double z_min_m = 0.0;
  double z_max_m = 2.2;
  double reflectivity = 0.4;
  std::vector<Vector2> path_m;  // at least two distinct points
  double speed_mps = 1.0;
  double phase_m = 0.0;
  std::shared_ptr<const core::Trajectory> trajectory;
  // A trajectory-driven obstacle that leaves after its last stamp (a fleet
  // robot that has driven off to its dock); false: it stays at its last pose.
  bool leaves_after_trajectory = false;

  bool IsCircle() const { return radius_m > 0.0; }
  // Whether it is on the floor at the stamp.
  bool PresentAt(double stamp_s) const {
    return !(leaves_after_trajectory && trajectory && !trajectory->empty() &&
             stamp_s > trajectory->back().stamp_s);
  }
  // T_map_obstacle at the stamp (x along the direction of travel).
  core::SE2 PoseAt(double stamp_s) const;
  // The footprint at the stamp (for boxes; circles give a square of the radius).
  OrientedBox FootprintAt(double stamp_s) const;
};

struct World {
  std::string name;
  // The zone's floor, walls included.
  Vector2 floor_min_m = Vector2::Zero();
  Vector2 floor_max_m = Vector2::Zero();
  std::vector<Obstacle> obstacles;
  std::vector<FloorMarking> markings;
  RoadGraph roads;
  std::vector<MovingObstacle> moving;
};

// Length of a polyline in metres.
double PolylineLength(const std::vector<Vector2>& polyline_m);

// trajectory_association.h: linear in x, y and shortest-way yaw, clamped.
using core::InterpolatePose;

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_WORLD_H_
