#include <cmath>
#include <random>
#include <vector>

#include "groundline/sim/zones.h"
#include "zone_builder.h"

namespace groundline::sim {
namespace {

using internal::CheckRange;
using internal::FirstError;
using internal::kTapeWidthM;

constexpr const char* kZoneCOwner = "ZoneCOptions";
constexpr double kTrailerLengthM = 13.6;
constexpr double kTrailerWidthM = 2.5;
constexpr double kRowGapM = 1.5;  // lane edge to staging lane

int NumGroups(const ZoneCOptions& o) {
  return (o.num_doors + o.doors_per_group - 1) / o.doors_per_group;
}

// Centre lines x of the connector lanes: at both ends and between door groups.
std::vector<double> ConnectorXs(const ZoneCOptions& o) {
  std::vector<double> xs = {0.5 * o.end_margin_m};
  const double group_m = o.doors_per_group * o.door_pitch_m;
  for (int g = 0; g + 1 < NumGroups(o); ++g) {
    xs.push_back(o.end_margin_m + (g + 1) * group_m + g * o.group_gap_m + 0.5 * o.group_gap_m);
  }
  xs.push_back(o.WidthM() - 0.5 * o.end_margin_m);
  return xs;
}

// Solid tape along y = const from x0 to x1, interrupted where lanes cross.
void AddInterruptedLine(internal::ZoneBuilder* b, double y, double x0, double x1,
                        const std::vector<double>& gaps_x, double gap_half_m, double wear) {
  double x = x0;
  for (double g : gaps_x) {
    if (g - gap_half_m > x) {
      b->AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {x, y}, {g - gap_half_m, y},
                 kTapeWidthM, wear);
    }
    x = std::max(x, g + gap_half_m);
  }
  if (x < x1)
    b->AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {x, y}, {x1, y}, kTapeWidthM, wear);
}

}  // namespace

core::Status ZoneCOptions::Validate() const {
  core::Status status = FirstError({
      CheckRange(kZoneCOwner, "num_doors", num_doors, 1, 200),
      CheckRange(kZoneCOwner, "doors_per_group", doors_per_group, 1, num_doors),
      CheckRange(kZoneCOwner, "door_width_m", door_width_m, 2.0, 6.0),
      CheckRange(kZoneCOwner, "door_pitch_m", door_pitch_m, door_width_m + 0.5, 20.0),
      CheckRange(kZoneCOwner, "lane_width_m", lane_width_m, 2.5, 10.0),
      CheckRange(kZoneCOwner, "group_gap_m", group_gap_m, lane_width_m, 50.0),
      CheckRange(kZoneCOwner, "end_margin_m", end_margin_m, lane_width_m + 1.0, 50.0),
      CheckRange(kZoneCOwner, "staging_lane_width_m", staging_lane_width_m, 1.2,
                 door_pitch_m - 0.3),
      CheckRange(kZoneCOwner, "staging_lane_length_m", staging_lane_length_m, 1.5, 100.0),
      CheckRange(kZoneCOwner, "main_lane_center_y_m", main_lane_center_y_m,
                 0.5 * lane_width_m + 1.0, 100.0),
      CheckRange(kZoneCOwner, "apron_lane_from_wall_m", apron_lane_from_wall_m,
                 0.5 * lane_width_m + 1.5, 50.0),
      CheckRange(kZoneCOwner, "door_open_probability", door_open_probability, 0.0, 1.0),
      CheckRange(kZoneCOwner, "trailer_probability", trailer_probability, 0.0, 1.0),
      CheckRange(kZoneCOwner, "pallet_occupancy", pallet_occupancy, 0.0, 1.0),
      CheckRange(kZoneCOwner, "tape_wear_fraction", tape_wear_fraction, 0.0, 1.0),
      CheckRange(kZoneCOwner, "joint_spacing_m", joint_spacing_m, 0.0, 100.0),
      CheckRange(kZoneCOwner, "num_forklifts", num_forklifts, 0, 100),
      CheckRange(kZoneCOwner, "num_pedestrians", num_pedestrians, 0, 100),
  });
  if (!status.ok()) return status;
  const double needed_m = main_lane_center_y_m + lane_width_m + 2.0 * kRowGapM +
                          staging_lane_length_m + apron_lane_from_wall_m;
  if (depth_m < needed_m) {
    return core::Status::Error(
        "ZoneCOptions.depth_m: expected at least " + std::to_string(needed_m) +
        " m to fit the lanes and one staging row, got " + std::to_string(depth_m));
  }
  return core::Status::Ok();
}

double ZoneCOptions::WidthM() const {
  const int groups = NumGroups(*this);
  return 2.0 * end_margin_m + groups * doors_per_group * door_pitch_m + (groups - 1) * group_gap_m;
}

double ZoneCOptions::DoorCenterXM(int door) const {
  const int g = door / doors_per_group;
  const int i = door % doors_per_group;
  return end_margin_m + g * (doors_per_group * door_pitch_m + group_gap_m) +
         (i + 0.5) * door_pitch_m;
}

core::Result<World> BuildZoneC(const ZoneCOptions& o) {
  if (core::Status status = o.Validate(); !status.ok()) return status;
  std::mt19937_64 rng(o.seed);
  internal::ZoneBuilder b("zone_c_loading_docks");
  const double W = o.WidthM();
  const double D = o.depth_m;
  const double half_lane = 0.5 * o.lane_width_m;
  const double wear = o.tape_wear_fraction;
  const double y_main = o.main_lane_center_y_m;
  const double y_apron = D - o.apron_lane_from_wall_m;

  b.AddWall({-0.15, -0.3}, {-0.15, D + 0.3});
  b.AddWall({W + 0.15, -0.3}, {W + 0.15, D + 0.3});
  b.AddWall({0.0, -0.15}, {W, -0.15});

  // The dock wall with its doors: closed, open onto the yard, or open with a
  // trailer docked (the trailer floor is level with the hall floor).
  std::bernoulli_distribution open(o.door_open_probability);
  std::bernoulli_distribution trailer(o.trailer_probability);
  double wall_x = 0.0;
  for (int d = 0; d < o.num_doors; ++d) {
    const double xd = o.DoorCenterXM(d);
    const double x0 = xd - 0.5 * o.door_width_m;
    const double x1 = xd + 0.5 * o.door_width_m;
    b.AddWall({wall_x, D + 0.15}, {x0, D + 0.15});
    wall_x = x1;
    if (!open(rng)) {
      b.AddAxisBox(ObstacleKind::kDockDoor, {x0, D + 0.1}, {x1, D + 0.2}, 0.0, 4.0);
    } else if (trailer(rng)) {
      const double half = 0.5 * kTrailerWidthM;
      const double ya = D + 0.3;
      const double yb = ya + kTrailerLengthM;
      b.AddAxisBox(ObstacleKind::kTrailer, {xd - half - 0.05, ya}, {xd - half, yb}, 0.0, 2.7);
      b.AddAxisBox(ObstacleKind::kTrailer, {xd + half, ya}, {xd + half + 0.05, yb}, 0.0, 2.7);
      b.AddAxisBox(ObstacleKind::kTrailer, {xd - half - 0.05, yb}, {xd + half + 0.05, yb + 0.05},
                   0.0, 2.7);
    }
    b.AddLine(MarkingKind::kStopBar, MarkingColour::kWhite, {xd - 1.4, D - 1.0},
              {xd + 1.4, D - 1.0}, 0.2, wear);
  }
  b.AddWall({wall_x, D + 0.15}, {W, D + 0.15});

  // Lanes and the road graph.
  const std::vector<double> cx = ConnectorXs(o);
  std::vector<int> main_nodes, apron_nodes;
  for (std::size_t k = 0; k < cx.size(); ++k) {
    main_nodes.push_back(b.AddNode({cx[k], y_main}));
    apron_nodes.push_back(b.AddNode({cx[k], y_apron}));
    b.AddEdge(main_nodes[k], apron_nodes[k], 1.5);
    if (k > 0) {
      b.AddEdge(main_nodes[k - 1], main_nodes[k]);
      b.AddEdge(apron_nodes[k - 1], apron_nodes[k]);
    }
    for (double side : {-half_lane, half_lane}) {
      b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {cx[k] + side, y_main + half_lane},
                {cx[k] + side, y_apron - half_lane}, kTapeWidthM, wear);
    }
  }
  b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {0.5, y_main - half_lane},
            {W - 0.5, y_main - half_lane}, kTapeWidthM, wear);
  AddInterruptedLine(&b, y_main + half_lane, 0.5, W - 0.5, cx, half_lane, wear);
  AddInterruptedLine(&b, y_apron - half_lane, 0.5, W - 0.5, cx, half_lane, wear);
  b.AddDashedLine(MarkingColour::kYellow, {0.5, y_apron + half_lane},
                  {W - 0.5, y_apron + half_lane}, kTapeWidthM, 1.0, 0.5, wear);

  // Staging lanes in front of every door (one or two rows), pallets in them,
  // columns between the rows.
  const double rows_hi = y_apron - half_lane - kRowGapM;
  const double rows_lo = y_main + half_lane + kRowGapM;
  std::vector<double> row_starts = {rows_hi - o.staging_lane_length_m};
  const bool two_rows = rows_lo + o.staging_lane_length_m <= row_starts[0] - 2.0;
  if (two_rows) row_starts.push_back(rows_lo);
  std::bernoulli_distribution occupied(o.pallet_occupancy);
  const int slots = static_cast<int>(std::floor((o.staging_lane_length_m - 0.2) / 1.3));
  for (int d = 0; d < o.num_doors; ++d) {
    const double xd = o.DoorCenterXM(d);
    for (double y0 : row_starts) {
      const Vector2 lo(xd - 0.5 * o.staging_lane_width_m, y0);
      const Vector2 hi(xd + 0.5 * o.staging_lane_width_m, y0 + o.staging_lane_length_m);
      b.AddStagingBox(lo, hi, MarkingColour::kWhite, kTapeWidthM, 0.75 * wear);
      for (int s = 0; s < slots; ++s) {
        if (!occupied(rng)) continue;
        const Vector2 center(xd + internal::Uniform(&rng, -0.1, 0.1), y0 + 0.75 + 1.3 * s);
        const double height_m = internal::Uniform(&rng, 0.5, 2.0);    // one draw per statement,
        const double yaw_rad = internal::Uniform(&rng, -0.05, 0.05);  // last first
        b.AddPalletStack(center, {1.0, 1.2}, yaw_rad, height_m);
      }
    }
    if (two_rows && d % o.doors_per_group == 1 && d + 1 < o.num_doors) {
      const Vector2 c(xd + 0.5 * o.door_pitch_m,
                      0.5 * (rows_lo + o.staging_lane_length_m + row_starts[0]));
      b.AddAxisBox(ObstacleKind::kColumn, c - Vector2(0.25, 0.25), c + Vector2(0.25, 0.25));
    }
  }

  if (o.joint_spacing_m > 0.0) {
    for (double x = o.joint_spacing_m; x < W; x += o.joint_spacing_m) b.AddJoint({x, 0}, {x, D});
    for (double y = o.joint_spacing_m; y < D; y += o.joint_spacing_m) b.AddJoint({0, y}, {W, y});
  }
  b.AddMovingObstacles(MovingKind::kForklift, o.num_forklifts, 1.0, &rng);
  b.AddMovingObstacles(MovingKind::kPedestrian, o.num_pedestrians, 1.6, &rng);
  return b.Finish({-0.3, -0.3}, {W + 0.3, D + 0.3});
}

}  // namespace groundline::sim
