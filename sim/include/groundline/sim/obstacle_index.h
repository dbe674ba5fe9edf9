// A uniform-grid spatial index over the edges of a World's static obstacles,
// for ray casting (the LiDAR) and clearance queries (route checks).
//
// Each obstacle footprint contributes its four edges; a grid cell lists every
// edge whose bounding box overlaps it. CastRay walks the cells the ray crosses
// (Amanatides & Woo, "A fast voxel traversal algorithm", 1987) and stops at the
// first cell whose exit lies beyond the nearest hit, so its cost grows with the
// distance to the first obstacle, not with the size of the world.
//
// The index copies what it needs; it does not refer to the World afterwards.
// All queries are const and thread-safe.
#ifndef GROUNDLINE_SIM_OBSTACLE_INDEX_H_
#define GROUNDLINE_SIM_OBSTACLE_INDEX_H_

#include <cstdint>
#include <limits>
#include <vector>

#include "groundline/core/segment_distance.h"
#include "groundline/core/status.h"
#include "groundline/sim/world.h"

namespace groundline::sim {

// The result of a ray cast. `range_m` is +infinity when nothing is hit within
// the maximum range.
struct RayHit {
  double range_m = std::numeric_limits<double>::infinity();
  int obstacle = -1;  // index into World::obstacles, -1 if no hit
  // |cos| of the angle between the ray and the surface normal, in [0, 1].
  double cos_incidence = 0.0;

  bool hit() const { return obstacle >= 0; }
};

// Ray against one segment a-b: the distance t >= 0 along the unit direction, or
// +infinity. cos_incidence is set on a hit (may be nullptr).
double IntersectRaySegment(const Vector2& origin_m, const Vector2& direction, const Vector2& a_m,
                           const Vector2& b_m, double* cos_incidence = nullptr);
// Ray against a circle; +infinity if missed or if the origin is inside.
double IntersectRayCircle(const Vector2& origin_m, const Vector2& direction,
                          const Vector2& center_m, double radius_m,
                          double* cos_incidence = nullptr);
// Distance from a point to a segment.
using core::DistanceToSegment;

class ObstacleIndex {
 public:
  struct Options {
    double cell_size_m = 0.5;
    // Index only obstacles that intersect the horizontal plane at this height
    // (the LiDAR plane); NaN indexes all obstacles (vehicle clearance).
    double plane_height_m = std::numeric_limits<double>::quiet_NaN();

    core::Status Validate() const;
  };

  // Asserts that options.Validate() is ok.
  ObstacleIndex(const World& world, const Options& options);

  // Nearest hit along the ray from origin_m in the unit direction, up to max_range_m.
  RayHit CastRay(const Vector2& origin_m, const Vector2& direction, double max_range_m) const;

  // Distance from the point to the nearest indexed obstacle: 0 if the point is
  // inside one, otherwise the distance to the nearest edge, capped at
  // search_radius_m (returned when nothing is nearer).
  double ClearanceM(const Vector2& point_m, double search_radius_m) const;

  std::size_t num_edges() const { return edges_.size(); }
  std::size_t num_obstacles() const { return boxes_.size(); }

 private:
  struct Edge {
    Vector2 a_m;
    Vector2 b_m;
    int obstacle = 0;  // index into World::obstacles
  };

  int CellX(double x_m) const;
  int CellY(double y_m) const;
  std::size_t CellIndex(int cx, int cy) const {
    return static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) +
           static_cast<std::size_t>(cx);
  }
  // Tests the ray against the edges listed in one cell, keeping the nearest hit.
  void TestCell(std::size_t cell, const Vector2& origin_m, const Vector2& direction,
                RayHit* best) const;

  Options options_;
  std::vector<OrientedBox> boxes_;
  std::vector<Edge> edges_;
  Vector2 origin_m_ = Vector2::Zero();  // lower-left corner of the grid
  int nx_ = 0;
  int ny_ = 0;
  // Compressed cell lists: edges of cell c are edge_ids_[cell_start_[c] .. cell_start_[c + 1]).
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> edge_ids_;
  // The same for boxes (containment tests).
  std::vector<std::uint32_t> cell_box_start_;
  std::vector<std::uint32_t> box_ids_;
};

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_OBSTACLE_INDEX_H_
