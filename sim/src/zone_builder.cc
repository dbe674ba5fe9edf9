#include "zone_builder.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace groundline::sim::internal {
namespace {

double ReflectivityOf(ObstacleKind kind) {
  switch (kind) {
    case ObstacleKind::kWall:
      return 0.55;
    case ObstacleKind::kColumn:
      return 0.5;
    case ObstacleKind::kRackUpright:
      return 0.35;
    case ObstacleKind::kRackBeam:
      return 0.35;
    case ObstacleKind::kPallet:
      return 0.6;
    case ObstacleKind::kDockDoor:
      return 0.7;
    case ObstacleKind::kTrailer:
      return 0.45;
  }
  return 0.5;
}

// Shifts a polyline sideways by offset_m (positive: to the right of travel),
// mitering the corners.
std::vector<Vector2> OffsetPolyline(const std::vector<Vector2>& points, double offset_m) {
  std::vector<Vector2> out;
  const std::size_t n = points.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vector2 d_in =
        i > 0 ? (points[i] - points[i - 1]).normalized() : (points[1] - points[0]).normalized();
    const Vector2 d_out = i + 1 < n ? (points[i + 1] - points[i]).normalized() : d_in;
    const Vector2 right_in(d_in.y(), -d_in.x());
    const Vector2 right_out(d_out.y(), -d_out.x());
    Vector2 miter = right_in + right_out;
    const double scale = miter.squaredNorm() > 1e-6 ? 2.0 / miter.squaredNorm() : 0.0;
    miter = scale > 0.0 ? Vector2(miter * scale) : right_in;
    out.push_back(points[i] + offset_m * miter);
  }
  return out;
}

}  // namespace

double Uniform(std::mt19937_64* rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(*rng);
}

void ZoneBuilder::AddBox(ObstacleKind kind, const OrientedBox& box, double z_min_m,
                         double z_max_m) {
  world_.obstacles.push_back({kind, box, z_min_m, z_max_m, ReflectivityOf(kind)});
}

void ZoneBuilder::AddAxisBox(ObstacleKind kind, const Vector2& min_m, const Vector2& max_m,
                             double z_min_m, double z_max_m) {
  AddBox(kind, OrientedBox::FromMinMax(min_m, max_m), z_min_m, z_max_m);
}

void ZoneBuilder::AddWall(const Vector2& a_m, const Vector2& b_m, double thickness_m) {
  AddBox(ObstacleKind::kWall, OrientedBox::AlongSegment(a_m, b_m, thickness_m), 0.0,
         kBuildingHeightM);
}

void ZoneBuilder::AddPalletStack(const Vector2& center_m, const Vector2& footprint_m,
                                 double yaw_rad, double height_m) {
  OrientedBox box;
  box.center_m = center_m;
  box.half_extent_m = 0.5 * footprint_m;
  box.yaw_rad = yaw_rad;
  AddBox(ObstacleKind::kPallet, box, 0.0, height_m);
}

void ZoneBuilder::AddLine(MarkingKind kind, MarkingColour colour, const Vector2& a_m,
                          const Vector2& b_m, double width_m, double wear_fraction) {
  FloorMarking m;
  m.kind = kind;
  m.colour = colour;
  m.polarity = colour == MarkingColour::kGroove ? MarkingPolarity::kDark : MarkingPolarity::kBright;
  m.polyline_m = {a_m, b_m};
  m.width_m = width_m;
  m.wear_fraction = wear_fraction;
  world_.markings.push_back(std::move(m));
}

void ZoneBuilder::AddDashedLine(MarkingColour colour, const Vector2& a_m, const Vector2& b_m,
                                double width_m, double dash_m, double gap_m, double wear_fraction) {
  AddLine(MarkingKind::kTapeDashed, colour, a_m, b_m, width_m, wear_fraction);
  world_.markings.back().dash_length_m = dash_m;
  world_.markings.back().gap_length_m = gap_m;
}

void ZoneBuilder::AddStagingBox(const Vector2& min_m, const Vector2& max_m, MarkingColour colour,
                                double width_m, double wear_fraction) {
  AddLine(MarkingKind::kStagingBoxEdge, colour, min_m, max_m, width_m, wear_fraction);
  world_.markings.back().polyline_m = {min_m, Vector2(max_m.x(), min_m.y()), max_m,
                                       Vector2(min_m.x(), max_m.y()), min_m};
}

void ZoneBuilder::AddCrosswalk(const Vector2& center_m, const Vector2& lane_dir, int num_stripes,
                               double stripe_length_m, double stripe_width_m, double pitch_m) {
  const Vector2 along = lane_dir.normalized();
  const Vector2 across(-along.y(), along.x());
  for (int i = 0; i < num_stripes; ++i) {
    const double offset_m = (i - 0.5 * (num_stripes - 1)) * pitch_m;
    const Vector2 c = center_m + offset_m * across;
    AddLine(MarkingKind::kCrosswalkStripe, MarkingColour::kWhite, c - 0.5 * stripe_length_m * along,
            c + 0.5 * stripe_length_m * along, stripe_width_m);
  }
}

void ZoneBuilder::AddJoint(const Vector2& a_m, const Vector2& b_m) {
  AddLine(MarkingKind::kJoint, MarkingColour::kGroove, a_m, b_m, kJointWidthM);
}

int ZoneBuilder::AddNode(const Vector2& p_m) {
  world_.roads.nodes_m.push_back(p_m);
  return static_cast<int>(world_.roads.nodes_m.size()) - 1;
}

void ZoneBuilder::AddEdge(int from, int to, double preference) {
  assert(from != to);
  world_.roads.edges.push_back({from, to, preference});
}

void ZoneBuilder::AddMovingObstacles(MovingKind kind, int count, double lateral_offset_m,
                                     std::mt19937_64* rng) {
  const RoadGraph& roads = world_.roads;
  if (roads.edges.empty()) return;
  for (int k = 0; k < count; ++k) {
    std::uniform_int_distribution<std::size_t> pick_edge(0, roads.edges.size() - 1);
    const RoadGraph::Edge& first = roads.edges[pick_edge(*rng)];
    std::vector<int> nodes = {first.from, first.to};
    const int num_edges = std::uniform_int_distribution<int>(2, 5)(*rng);
    for (int e = 1; e < num_edges; ++e) {
      std::vector<int> next;
      for (const RoadGraph::Edge& edge : roads.edges) {
        const int cur = nodes.back();
        const int prev = nodes[nodes.size() - 2];
        if (edge.from == cur && edge.to != prev) next.push_back(edge.to);
        if (edge.to == cur && edge.from != prev) next.push_back(edge.from);
      }
      if (next.empty()) break;
      nodes.push_back(next[std::uniform_int_distribution<std::size_t>(0, next.size() - 1)(*rng)]);
    }
    std::vector<Vector2> path;
    for (int n : nodes) path.push_back(roads.nodes_m[static_cast<std::size_t>(n)]);
    MovingObstacle m;
    m.kind = kind;
    m.path_m = OffsetPolyline(path, lateral_offset_m);
    if (kind == MovingKind::kForklift) {
      m.half_extent_m = Vector2(1.3, 0.6);
      m.z_max_m = 2.2;
      m.reflectivity = 0.4;
      m.speed_mps = Uniform(rng, 1.0, 2.5);
    } else {
      m.radius_m = 0.2;
      m.z_max_m = 1.8;
      m.reflectivity = 0.3;
      m.speed_mps = Uniform(rng, 0.8, 1.5);
    }
    m.phase_m = Uniform(rng, 0.0, 2.0 * PolylineLength(m.path_m));
    world_.moving.push_back(std::move(m));
  }
}

World ZoneBuilder::Finish(const Vector2& floor_min_m, const Vector2& floor_max_m) {
  world_.floor_min_m = floor_min_m;
  world_.floor_max_m = floor_max_m;
  return std::move(world_);
}

}  // namespace groundline::sim::internal
