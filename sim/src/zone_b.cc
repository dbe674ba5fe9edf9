#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "groundline/sim/zones.h"
#include "zone_builder.h"

namespace groundline::sim {
namespace {

using internal::CheckRange;
using internal::FirstError;
using internal::kTapeWidthM;

constexpr const char* kZoneBOwner = "ZoneBOptions";

// One rack row along y: uprights at its front (aisle side) and back faces, the
// beam stack above first_beam_height_m, ground-level pallets. front_x_m is the
// x of the face towards the aisle; `toward_aisle` is +1 if the aisle lies at
// larger x.
void AddRackRow(const ZoneBOptions& o, double front_x_m, double toward_aisle,
                std::bernoulli_distribution* fill, std::mt19937_64* rng, internal::ZoneBuilder* b) {
  const double y0 = o.RackStartYM();
  const double y1 = y0 + o.aisle_length_m;
  const double back_x_m = front_x_m - toward_aisle * o.rack_depth_m;
  auto x_span = [&](double from_x, double depth) {
    const double other = from_x - toward_aisle * depth;
    return std::pair(std::min(from_x, other), std::max(from_x, other));
  };
  std::vector<double> upright_y;
  for (double y = y0; y + o.upright_width_m <= y1 + 1e-9; y += o.upright_pitch_m) {
    upright_y.push_back(y);
  }
  if (y1 - o.upright_width_m - upright_y.back() > 1e-6) upright_y.push_back(y1 - o.upright_width_m);

  // Faces of the rack seen from outside: the front (aisle side) and the back.
  for (const auto& [face, outward] :
       {std::pair(front_x_m, toward_aisle), std::pair(back_x_m, -toward_aisle)}) {
    const double xa = std::min(face, face - outward * o.upright_depth_m);
    const double xb = std::max(face, face - outward * o.upright_depth_m);
    for (double y : upright_y) {
      b->AddAxisBox(ObstacleKind::kRackUpright, {xa, y}, {xb, y + o.upright_width_m}, 0.0,
                    o.rack_height_m);
    }
    const double ba = std::min(face, face - outward * 0.12);
    const double bb = std::max(face, face - outward * 0.12);
    b->AddAxisBox(ObstacleKind::kRackBeam, {ba, y0}, {bb, y1}, o.first_beam_height_m,
                  o.rack_height_m);
  }
  // Ground-level pallets, evenly spaced in each full bay.
  const auto [pa, pb] = x_span(front_x_m - toward_aisle * o.pallet_setback_m, o.pallet_depth_m);
  for (std::size_t k = 0; k + 1 < upright_y.size(); ++k) {
    const double bay_lo = upright_y[k] + o.upright_width_m;
    const double bay_m = upright_y[k + 1] - bay_lo;
    const double gap = (bay_m - o.pallets_per_bay * o.pallet_width_m) / (o.pallets_per_bay + 1);
    if (gap < 0.0) continue;  // a short end bay
    for (int p = 0; p < o.pallets_per_bay; ++p) {
      if (!(*fill)(*rng)) continue;
      const double y = bay_lo + gap + p * (o.pallet_width_m + gap);
      b->AddAxisBox(ObstacleKind::kPallet, {pa, y}, {pb, y + o.pallet_width_m}, 0.0,
                    o.pallet_height_m);
    }
  }
}

}  // namespace

core::Status ZoneBOptions::Validate() const {
  core::Status status = FirstError({
      CheckRange(kZoneBOwner, "num_aisles", num_aisles, 1, 200),
      CheckRange(kZoneBOwner, "aisle_length_m", aisle_length_m, 5.0, 500.0),
      CheckRange(kZoneBOwner, "aisle_clear_width_m", aisle_clear_width_m, 1.5, 10.0),
      CheckRange(kZoneBOwner, "upright_width_m", upright_width_m, 0.02, 0.5),
      CheckRange(kZoneBOwner, "upright_pitch_m", upright_pitch_m, upright_width_m + 0.5, 10.0),
      CheckRange(kZoneBOwner, "upright_depth_m", upright_depth_m, 0.02, 0.5),
      CheckRange(kZoneBOwner, "rack_depth_m", rack_depth_m, 2.0 * upright_depth_m + 0.1, 3.0),
      CheckRange(kZoneBOwner, "flue_gap_m", flue_gap_m, 0.0, 2.0),
      CheckRange(kZoneBOwner, "wall_gap_m", wall_gap_m, 0.0, 2.0),
      CheckRange(kZoneBOwner, "cross_aisle_width_m", cross_aisle_width_m, 2.5, 20.0),
      CheckRange(kZoneBOwner, "rack_height_m", rack_height_m, 2.0, 40.0),
      CheckRange(kZoneBOwner, "first_beam_height_m", first_beam_height_m, 0.05, rack_height_m),
      CheckRange(kZoneBOwner, "pallets_per_bay", pallets_per_bay, 0, 10),
      CheckRange(kZoneBOwner, "pallet_width_m", pallet_width_m, 0.2, 3.0),
      CheckRange(kZoneBOwner, "pallet_depth_m", pallet_depth_m, 0.2, rack_depth_m),
      CheckRange(kZoneBOwner, "pallet_height_m", pallet_height_m, 0.05, first_beam_height_m),
      CheckRange(kZoneBOwner, "pallet_setback_m", pallet_setback_m, 0.0,
                 rack_depth_m - pallet_depth_m),
      CheckRange(kZoneBOwner, "pallet_fill", pallet_fill, 0.0, 1.0),
      CheckRange(kZoneBOwner, "tape_offset_m", tape_offset_m, 0.0, 0.25 * aisle_clear_width_m),
      CheckRange(kZoneBOwner, "stop_bar_width_m", stop_bar_width_m, 0.02, 1.0),
      CheckRange(kZoneBOwner, "stop_bar_inset_m", stop_bar_inset_m, 0.0, 0.5 * aisle_length_m),
      CheckRange(kZoneBOwner, "joint_spacing_m", joint_spacing_m, 0.0, 100.0),
      CheckRange(kZoneBOwner, "num_pedestrians", num_pedestrians, 0, 100),
  });
  if (!status.ok()) return status;
  if (pallets_per_bay * pallet_width_m > upright_pitch_m - upright_width_m) {
    return core::Status::Error(
        "ZoneBOptions: pallets_per_bay * pallet_width_m exceeds the bay between uprights "
        "(upright_pitch_m - upright_width_m); reduce pallets_per_bay or pallet_width_m");
  }
  return core::Status::Ok();
}

double ZoneBOptions::AisleCenterXM(int i) const {
  return wall_gap_m + rack_depth_m + 0.5 * aisle_clear_width_m + i * AislePitchM();
}

core::Result<World> BuildZoneB(const ZoneBOptions& o) {
  if (core::Status status = o.Validate(); !status.ok()) return status;
  std::mt19937_64 rng(o.seed);
  std::bernoulli_distribution fill(o.pallet_fill);
  internal::ZoneBuilder b("zone_b_high_bay_racks");
  const double half_w = 0.5 * o.aisle_clear_width_m;
  const double W = o.AisleCenterXM(o.num_aisles - 1) + half_w + o.rack_depth_m + o.wall_gap_m;
  const double y0 = o.RackStartYM();
  const double y1 = y0 + o.aisle_length_m;
  const double D = y1 + o.cross_aisle_width_m;

  b.AddWall({-0.15, -0.3}, {-0.15, D + 0.3});
  b.AddWall({W + 0.15, -0.3}, {W + 0.15, D + 0.3});
  b.AddWall({0.0, -0.15}, {W, -0.15});
  b.AddWall({0.0, D + 0.15}, {W, D + 0.15});

  std::vector<int> south, north;
  for (int i = 0; i < o.num_aisles; ++i) {
    const double xc = o.AisleCenterXM(i);
    AddRackRow(o, xc - half_w, +1.0, &fill, &rng, &b);
    AddRackRow(o, xc + half_w, -1.0, &fill, &rng, &b);
    for (double side : {-1.0, 1.0}) {
      const double x = xc + side * (half_w - o.tape_offset_m);
      b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {x, y0}, {x, y1}, kTapeWidthM);
    }
    const double bar_half = half_w - o.tape_offset_m - 0.5 * kTapeWidthM;
    for (double y : {y0 + o.stop_bar_inset_m, y1 - o.stop_bar_inset_m}) {
      b.AddLine(MarkingKind::kStopBar, MarkingColour::kWhite, {xc - bar_half, y},
                {xc + bar_half, y}, o.stop_bar_width_m);
    }
    south.push_back(b.AddNode({xc, 0.5 * o.cross_aisle_width_m}));
    north.push_back(b.AddNode({xc, y1 + 0.5 * o.cross_aisle_width_m}));
    // Aisles are preferred over cross-aisle hops: routes traverse aisles end to end.
    b.AddEdge(south.back(), north.back(), 4.0);
    if (i > 0) {
      b.AddEdge(south[i - 1], south[i]);
      b.AddEdge(north[i - 1], north[i]);
    }
  }
  // Cross-aisle boundary lines along the end walls.
  for (double y : {0.5, D - 0.5}) {
    b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {0.5, y}, {W - 0.5, y}, kTapeWidthM);
  }
  if (o.joint_spacing_m > 0.0) {
    for (double y = o.joint_spacing_m; y < D; y += o.joint_spacing_m) b.AddJoint({0, y}, {W, y});
  }
  b.AddMovingObstacles(MovingKind::kPedestrian, o.num_pedestrians, 0.6, &rng);
  return b.Finish({-0.3, -0.3}, {W + 0.3, D + 0.3});
}

}  // namespace groundline::sim
