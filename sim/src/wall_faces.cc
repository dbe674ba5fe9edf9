#include "groundline/sim/wall_faces.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

#include "groundline/sim/obstacle_index.h"

namespace groundline::sim {
namespace {

bool IsStructure(ObstacleKind kind) {
  return kind == ObstacleKind::kWall || kind == ObstacleKind::kColumn ||
         kind == ObstacleKind::kRackUpright || kind == ObstacleKind::kDockDoor;
}

// A visible piece of an edge: the outward normal's angle, the offset along
// it, and the interval along the direction d = (-n.y, n.x).
struct Piece {
  double angle_rad = 0.0;
  double offset_m = 0.0;
  double s0_m = 0.0;
  double s1_m = 0.0;
};

void AddVisiblePieces(const Vector2& a, const Vector2& b, const Vector2& outward,
                      const ObstacleIndex& index, const WallFaceOptions& o,
                      std::vector<Piece>* pieces) {
  const double length = (b - a).norm();
  const Vector2 along = (b - a) / length;
  const int n = std::max(1, static_cast<int>(std::ceil(length / o.sample_step_m)));
  const double step = length / n;
  const Vector2 d(-outward.y(), outward.x());
  const double offset = outward.dot(a);
  const double sa = d.dot(a);
  const double sign = d.dot(along);  // +-1
  int run_start = -1;
  for (int k = 0; k <= n; ++k) {
    bool visible = false;
    if (k < n) {
      const Vector2 sample = a + (k + 0.5) * step * along;
      visible = index.ClearanceM(sample + o.clearance_offset_m * outward, o.clearance_radius_m) >=
                o.clearance_radius_m;
    }
    if (visible && run_start < 0) run_start = k;
    if (!visible && run_start >= 0) {
      const double u0 = sa + sign * run_start * step;
      const double u1 = sa + sign * k * step;
      pieces->push_back(
          {std::atan2(outward.y(), outward.x()), offset, std::min(u0, u1), std::max(u0, u1)});
      run_start = -1;
    }
  }
}

}  // namespace

core::Status WallFaceOptions::Validate() const {
  for (const auto& [field, value] :
       {std::pair("sample_step_m", sample_step_m),
        std::pair("clearance_offset_m", clearance_offset_m),
        std::pair("clearance_radius_m", clearance_radius_m),
        std::pair("merge_offset_m", merge_offset_m), std::pair("min_length_m", min_length_m),
        std::pair("min_recess_m", min_recess_m)}) {
    if (!(value > 0.0)) {
      return core::Status::Error(std::string("WallFaceOptions.") + field +
                                 ": expected a value > 0, got " + std::to_string(value));
    }
  }
  if (!(max_setback_m > 0.0) || !(min_backed_fraction >= 0.0 && min_backed_fraction <= 1.0)) {
    return core::Status::Error(
        "WallFaceOptions: expected max_setback_m > 0 and min_backed_fraction in [0, 1]");
  }
  if (!(max_gap_m >= 0.0)) return core::Status::Error("WallFaceOptions.max_gap_m: expected >= 0");
  if (!(clearance_radius_m < clearance_offset_m)) {
    return core::Status::Error(
        "WallFaceOptions: clearance_radius_m must be < clearance_offset_m (the disc would touch "
        "the face)");
  }
  return core::Status::Ok();
}

std::vector<WallFace> WallFaces(const World& world, const WallFaceOptions& o) {
  assert(o.Validate().ok());
  ObstacleIndex::Options index_options;
  index_options.plane_height_m = o.plane_height_m;
  const ObstacleIndex index(world, index_options);
  std::vector<Piece> pieces;
  for (const Obstacle& obstacle : world.obstacles) {
    if (!IsStructure(obstacle.kind) || !obstacle.IntersectsPlane(o.plane_height_m)) continue;
    const auto corners = obstacle.box.Corners();  // counter-clockwise
    for (int k = 0; k < 4; ++k) {
      const Vector2& a = corners[k];
      const Vector2& b = corners[(k + 1) % 4];
      const Vector2 e = (b - a).normalized();
      AddVisiblePieces(a, b, Vector2(e.y(), -e.x()), index, o, &pieces);
    }
  }
  std::sort(pieces.begin(), pieces.end(), [](const Piece& p, const Piece& q) {
    if (p.angle_rad != q.angle_rad) return p.angle_rad < q.angle_rad;
    if (p.offset_m != q.offset_m) return p.offset_m < q.offset_m;
    return p.s0_m < q.s0_m;
  });
  // A gap between pieces is part of the face (backed) when the surface
  // behind it (loads between uprights) is at most max_setback_m back on at
  // least min_backed_fraction of it: what the LiDAR sees there is then the
  // face's recessed band, not an opening (row ends with their loads 0.3 m
  // in). It is recessed when the face line itself is open there on at least
  // half of it (the loads stand at least min_recess_m behind it), not a
  // solid face hidden from the open floor by something in front of it.
  struct Gap {
    bool backed = true;
    bool recessed = false;
  };
  const auto gap = [&](const Piece& group, double s0, double s1) {
    const Vector2 n(std::cos(group.angle_rad), std::sin(group.angle_rad));
    const Vector2 d(-n.y(), n.x());
    const double r = 0.5 * o.max_setback_m;
    int samples = 0, hits = 0, open = 0;
    for (double u = s0 + 0.5 * o.sample_step_m; u < s1; u += o.sample_step_m) {
      const Vector2 on_face = group.offset_m * n + u * d;
      ++samples;
      hits += index.ClearanceM(on_face - r * n, r) < r;
      open += index.ClearanceM(on_face, o.min_recess_m) >= o.min_recess_m;
    }
    if (samples == 0) return Gap{};
    return Gap{hits >= o.min_backed_fraction * samples, 2 * open >= samples};
  };
  std::vector<WallFace> faces;
  const auto emit = [&](const Piece& group, double s0, double s1, bool rack_face) {
    if (s1 - s0 < o.min_length_m) return;
    const Vector2 n(std::cos(group.angle_rad), std::sin(group.angle_rad));
    const Vector2 d(-n.y(), n.x());
    faces.push_back({group.offset_m * n + s0 * d, group.offset_m * n + s1 * d, n, rack_face});
  };
  for (std::size_t begin = 0; begin < pieces.size();) {
    std::size_t end = begin + 1;
    while (end < pieces.size() &&
           std::abs(pieces[end].angle_rad - pieces[begin].angle_rad) < 1e-6 &&
           pieces[end].offset_m - pieces[end - 1].offset_m < o.merge_offset_m) {
      ++end;
    }
    std::vector<Piece> group(pieces.begin() + begin, pieces.begin() + end);
    std::sort(group.begin(), group.end(),
              [](const Piece& p, const Piece& q) { return p.s0_m < q.s0_m; });
    double s0 = group.front().s0_m, s1 = group.front().s1_m;
    bool rack_face = false;
    for (const Piece& p : group) {
      const Gap g = p.s0_m > s1 && p.s0_m - s1 <= o.max_gap_m ? gap(group.front(), s1, p.s0_m)
                                                              : Gap{};
      if (p.s0_m - s1 > o.max_gap_m || !g.backed) {
        emit(group.front(), s0, s1, rack_face);
        s0 = p.s0_m;
        rack_face = false;
      } else {
        rack_face = rack_face || g.recessed;
      }
      s1 = std::max(s1, p.s1_m);
    }
    emit(group.front(), s0, s1, rack_face);
    begin = end;
  }
  return faces;
}

}  // namespace groundline::sim
