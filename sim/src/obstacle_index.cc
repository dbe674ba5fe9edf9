#include "groundline/sim/obstacle_index.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

namespace groundline::sim {
namespace {

constexpr double kNoHit = std::numeric_limits<double>::infinity();

double Cross(const Vector2& a, const Vector2& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

double IntersectRaySegment(const Vector2& origin_m, const Vector2& direction, const Vector2& a_m,
                           const Vector2& b_m, double* cos_incidence) {
  const Vector2 e = b_m - a_m;
  const double denom = Cross(direction, e);
  if (denom == 0.0) return kNoHit;  // parallel: grazing rays do not return
  const Vector2 w = a_m - origin_m;
  const double t = Cross(w, e) / denom;
  const double u = Cross(w, direction) / denom;
  if (t < 0.0 || u < 0.0 || u > 1.0) return kNoHit;
  if (cos_incidence != nullptr) *cos_incidence = std::abs(denom) / e.norm();
  return t;
}

double IntersectRayCircle(const Vector2& origin_m, const Vector2& direction,
                          const Vector2& center_m, double radius_m, double* cos_incidence) {
  const Vector2 oc = origin_m - center_m;
  const double b = oc.dot(direction);
  const double c = oc.squaredNorm() - radius_m * radius_m;
  if (c <= 0.0) return kNoHit;
  const double disc = b * b - c;
  if (disc < 0.0) return kNoHit;
  const double t = -b - std::sqrt(disc);
  if (t < 0.0) return kNoHit;
  if (cos_incidence != nullptr) {
    const Vector2 normal = (oc + t * direction) / radius_m;
    *cos_incidence = std::abs(normal.dot(direction));
  }
  return t;
}

core::Status ObstacleIndex::Options::Validate() const {
  if (!(cell_size_m > 0.01 && cell_size_m <= 100.0)) {
    return core::Status::Error("ObstacleIndex: cell_size_m must be in (0.01, 100] m, got " +
                               std::to_string(cell_size_m));
  }
  return core::Status::Ok();
}

ObstacleIndex::ObstacleIndex(const World& world, const Options& options) : options_(options) {
  assert(options.Validate().ok());
  const bool all = std::isnan(options.plane_height_m);
  Vector2 lo(kNoHit, kNoHit);
  Vector2 hi(-kNoHit, -kNoHit);
  for (std::size_t i = 0; i < world.obstacles.size(); ++i) {
    const Obstacle& obstacle = world.obstacles[i];
    if (!all && !obstacle.IntersectsPlane(options.plane_height_m)) continue;
    boxes_.push_back(obstacle.box);
    const auto corners = obstacle.box.Corners();
    for (int k = 0; k < 4; ++k) {
      edges_.push_back({corners[k], corners[(k + 1) % 4], static_cast<int>(i)});
      lo = lo.cwiseMin(corners[k]);
      hi = hi.cwiseMax(corners[k]);
    }
  }
  if (edges_.empty()) {
    lo = hi = Vector2::Zero();
  }
  const double cell = options_.cell_size_m;
  origin_m_ = lo - Vector2(cell, cell);
  nx_ = static_cast<int>(std::ceil((hi.x() - origin_m_.x()) / cell)) + 1;
  ny_ = static_cast<int>(std::ceil((hi.y() - origin_m_.y()) / cell)) + 1;

  // Cell lists in two passes (count, then fill): edges by their bounding
  // boxes, boxes by theirs.
  const std::size_t num_cells = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  auto build = [&](std::size_t count, auto&& bounds, std::vector<std::uint32_t>* start,
                   std::vector<std::uint32_t>* ids) {
    start->assign(num_cells + 1, 0);
    auto for_each_cell = [&](std::size_t i, auto&& visit) {
      Vector2 lo_i, hi_i;
      bounds(i, &lo_i, &hi_i);
      for (int cy = CellY(lo_i.y()); cy <= CellY(hi_i.y()); ++cy) {
        for (int cx = CellX(lo_i.x()); cx <= CellX(hi_i.x()); ++cx) visit(CellIndex(cx, cy));
      }
    };
    for (std::size_t i = 0; i < count; ++i) {
      for_each_cell(i, [&](std::size_t c) { ++(*start)[c + 1]; });
    }
    for (std::size_t c = 0; c < num_cells; ++c) (*start)[c + 1] += (*start)[c];
    ids->resize((*start)[num_cells]);
    std::vector<std::uint32_t> fill(start->begin(), start->end() - 1);
    for (std::size_t i = 0; i < count; ++i) {
      for_each_cell(i, [&](std::size_t c) { (*ids)[fill[c]++] = static_cast<std::uint32_t>(i); });
    }
  };
  build(
      edges_.size(),
      [&](std::size_t i, Vector2* lo_i, Vector2* hi_i) {
        *lo_i = edges_[i].a_m.cwiseMin(edges_[i].b_m);
        *hi_i = edges_[i].a_m.cwiseMax(edges_[i].b_m);
      },
      &cell_start_, &edge_ids_);
  build(
      boxes_.size(),
      [&](std::size_t i, Vector2* lo_i, Vector2* hi_i) {
        const auto corners = boxes_[i].Corners();
        *lo_i = *hi_i = corners[0];
        for (const Vector2& c : corners) {
          *lo_i = lo_i->cwiseMin(c);
          *hi_i = hi_i->cwiseMax(c);
        }
      },
      &cell_box_start_, &box_ids_);
}

int ObstacleIndex::CellX(double x_m) const {
  const int c = static_cast<int>(std::floor((x_m - origin_m_.x()) / options_.cell_size_m));
  return std::clamp(c, 0, nx_ - 1);
}

int ObstacleIndex::CellY(double y_m) const {
  const int c = static_cast<int>(std::floor((y_m - origin_m_.y()) / options_.cell_size_m));
  return std::clamp(c, 0, ny_ - 1);
}

void ObstacleIndex::TestCell(std::size_t cell, const Vector2& origin_m, const Vector2& direction,
                             RayHit* best) const {
  for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
    const Edge& e = edges_[edge_ids_[k]];
    double cos_incidence = 0.0;
    const double t = IntersectRaySegment(origin_m, direction, e.a_m, e.b_m, &cos_incidence);
    if (t < best->range_m) {
      best->range_m = t;
      best->obstacle = e.obstacle;
      best->cos_incidence = cos_incidence;
    }
  }
}

RayHit ObstacleIndex::CastRay(const Vector2& origin_m, const Vector2& direction,
                              double max_range_m) const {
  RayHit best;
  if (edges_.empty()) return best;
  const double cell = options_.cell_size_m;
  // Clip the ray to the grid rectangle (slab test).
  const Vector2 grid_max = origin_m_ + cell * Vector2(nx_, ny_);
  double t0 = 0.0;
  double t1 = max_range_m;
  for (int axis = 0; axis < 2; ++axis) {
    const double d = direction[axis];
    if (d == 0.0) {
      if (origin_m[axis] < origin_m_[axis] || origin_m[axis] > grid_max[axis]) return best;
      continue;
    }
    double ta = (origin_m_[axis] - origin_m[axis]) / d;
    double tb = (grid_max[axis] - origin_m[axis]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return best;

  const Vector2 start = origin_m + t0 * direction;
  int cx = CellX(start.x());
  int cy = CellY(start.y());
  const int step_x = direction.x() > 0.0 ? 1 : -1;
  const int step_y = direction.y() > 0.0 ? 1 : -1;
  auto next_boundary_t = [&](int c, int step, int axis) {
    if (direction[axis] == 0.0) return kNoHit;
    const double boundary = origin_m_[axis] + cell * (step > 0 ? c + 1 : c);
    return (boundary - origin_m[axis]) / direction[axis];
  };
  double t_max_x = next_boundary_t(cx, step_x, 0);
  double t_max_y = next_boundary_t(cy, step_y, 1);
  const double t_delta_x = direction.x() != 0.0 ? cell / std::abs(direction.x()) : kNoHit;
  const double t_delta_y = direction.y() != 0.0 ? cell / std::abs(direction.y()) : kNoHit;

  while (true) {
    TestCell(CellIndex(cx, cy), origin_m, direction, &best);
    const double t_exit = std::min(t_max_x, t_max_y);
    if (best.range_m <= t_exit || t_exit > t1) break;
    if (t_max_x < t_max_y) {
      cx += step_x;
      t_max_x += t_delta_x;
      if (cx < 0 || cx >= nx_) break;
    } else {
      cy += step_y;
      t_max_y += t_delta_y;
      if (cy < 0 || cy >= ny_) break;
    }
  }
  if (best.range_m > max_range_m) best = RayHit();
  return best;
}

double ObstacleIndex::ClearanceM(const Vector2& point_m, double search_radius_m) const {
  assert(search_radius_m > 0.0);
  double nearest_m = search_radius_m;
  if (edges_.empty()) return nearest_m;
  const int x0 = CellX(point_m.x() - search_radius_m);
  const int x1 = CellX(point_m.x() + search_radius_m);
  const int y0 = CellY(point_m.y() - search_radius_m);
  const int y1 = CellY(point_m.y() + search_radius_m);
  for (int cy = y0; cy <= y1; ++cy) {
    for (int cx = x0; cx <= x1; ++cx) {
      const std::size_t c = CellIndex(cx, cy);
      for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const Edge& e = edges_[edge_ids_[k]];
        nearest_m = std::min(nearest_m, DistanceToSegment(point_m, e.a_m, e.b_m));
      }
    }
  }
  // A point deep inside a large box may be far from every edge.
  const std::size_t c = CellIndex(CellX(point_m.x()), CellY(point_m.y()));
  for (std::uint32_t k = cell_box_start_[c]; k < cell_box_start_[c + 1]; ++k) {
    if (boxes_[box_ids_[k]].Contains(point_m)) return 0.0;
  }
  return nearest_m;
}

}  // namespace groundline::sim
