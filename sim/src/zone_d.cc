#include <cmath>
#include <random>
#include <vector>

#include "groundline/sim/zones.h"
#include "zone_builder.h"

namespace groundline::sim {
namespace {

using internal::CheckRange;
using internal::FirstError;

constexpr const char* kZoneDOwner = "ZoneDOptions";

// Yellow boundary line along x at height y from x0 to x1, interrupted by the
// openings [c - half, c + half] of the cross corridors.
void AddBoundaryAlongX(internal::ZoneBuilder* b, const ZoneDOptions& o, double y, double x0,
                       double x1, const std::vector<double>& openings, double half) {
  double x = x0;
  for (double c : openings) {
    if (c - half > x) {
      b->AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {x, y}, {c - half, y},
                 o.boundary_line_width_m);
    }
    x = std::max(x, c + half);
  }
  if (x < x1) {
    b->AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {x, y}, {x1, y},
               o.boundary_line_width_m);
  }
}

}  // namespace

core::Status ZoneDOptions::Validate() const {
  return FirstError({
      CheckRange(kZoneDOwner, "corridor_width_m", corridor_width_m, 2.5, 20.0),
      CheckRange(kZoneDOwner, "num_cross_corridors", num_cross_corridors, 2, 50),
      CheckRange(kZoneDOwner, "corridor_length_m", corridor_length_m,
                 num_cross_corridors * (corridor_width_m + 5.0), 5000.0),
      CheckRange(kZoneDOwner, "corridor_separation_m", corridor_separation_m,
                 corridor_width_m + 5.0, 1000.0),
      CheckRange(kZoneDOwner, "joint_spacing_m", joint_spacing_m, 0.5, 100.0),
      CheckRange(kZoneDOwner, "boundary_line_offset_m", boundary_line_offset_m, 0.05,
                 0.3 * corridor_width_m),
      CheckRange(kZoneDOwner, "boundary_line_width_m", boundary_line_width_m, 0.02, 0.3),
      CheckRange(kZoneDOwner, "num_forklifts", num_forklifts, 0, 100),
      CheckRange(kZoneDOwner, "num_pedestrians", num_pedestrians, 0, 100),
  });
}

double ZoneDOptions::CrossCorridorCenterXM(int k) const {
  return 0.5 * corridor_width_m +
         k * (corridor_length_m - corridor_width_m) / (num_cross_corridors - 1);
}

core::Result<World> BuildZoneD(const ZoneDOptions& o) {
  if (core::Status status = o.Validate(); !status.ok()) return status;
  std::mt19937_64 rng(o.seed);
  internal::ZoneBuilder b("zone_d_corridors");
  const double L = o.corridor_length_m;
  const double w = o.corridor_width_m;
  const double half = 0.5 * w;
  const double y_north = o.corridor_separation_m;  // south edge of the north corridor
  const double D = y_north + w;
  const double off = o.boundary_line_offset_m;

  b.AddWall({-0.15, -0.3}, {-0.15, D + 0.3});
  b.AddWall({L + 0.15, -0.3}, {L + 0.15, D + 0.3});
  b.AddWall({0.0, -0.15}, {L, -0.15});
  b.AddWall({0.0, D + 0.15}, {L, D + 0.15});

  std::vector<double> xs;
  for (int k = 0; k < o.num_cross_corridors; ++k) xs.push_back(o.CrossCorridorCenterXM(k));
  // Solid blocks between the corridors: their faces are the smooth walls.
  for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
    b.AddAxisBox(ObstacleKind::kWall, {xs[k] + half, w}, {xs[k + 1] - half, y_north});
  }

  // Boundary lines: along the outer walls without interruption, along the
  // block faces interrupted by the cross-corridor openings.
  std::vector<int> south, north;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    south.push_back(b.AddNode({xs[k], half}));
    north.push_back(b.AddNode({xs[k], y_north + half}));
    b.AddEdge(south[k], north[k]);
    if (k > 0) {
      b.AddEdge(south[k - 1], south[k]);
      b.AddEdge(north[k - 1], north[k]);
    }
    const double xl = xs[k] - half + off;
    const double xr = xs[k] + half - off;
    const bool west_end = k == 0;
    const bool east_end = k + 1 == xs.size();
    b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {xl, west_end ? off : w},
              {xl, west_end ? D - off : y_north}, o.boundary_line_width_m);
    b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {xr, east_end ? off : w},
              {xr, east_end ? D - off : y_north}, o.boundary_line_width_m);
  }
  const double x0 = off + o.boundary_line_width_m;
  const double x1 = L - off - o.boundary_line_width_m;
  b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {x0, off}, {x1, off},
            o.boundary_line_width_m);
  b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {x0, D - off}, {x1, D - off},
            o.boundary_line_width_m);
  AddBoundaryAlongX(&b, o, w - off, x0, x1, xs, half - off);
  AddBoundaryAlongX(&b, o, y_north + off, x0, x1, xs, half - off);

  // Saw-cut joints across every corridor, every joint_spacing_m: along the
  // long corridors at x = k * spacing, along the cross corridors at
  // y = k * spacing (the slab's joint grid, seen only inside the corridors).
  for (double x = o.joint_spacing_m; x < L; x += o.joint_spacing_m) {
    b.AddJoint({x, 0.0}, {x, w});
    b.AddJoint({x, y_north}, {x, D});
  }
  for (double y = o.joint_spacing_m; y < D; y += o.joint_spacing_m) {
    if (y <= w || y >= y_north) continue;
    for (double xc : xs) b.AddJoint({xc - half, y}, {xc + half, y});
  }

  b.AddMovingObstacles(MovingKind::kForklift, o.num_forklifts, 0.9, &rng);
  b.AddMovingObstacles(MovingKind::kPedestrian, o.num_pedestrians, 1.2, &rng);
  return b.Finish({-0.3, -0.3}, {L + 0.3, D + 0.3});
}

}  // namespace groundline::sim
