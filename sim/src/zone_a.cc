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

constexpr const char* kZoneAOwner = "ZoneAOptions";

std::vector<double> LaneCenters(int count, double extent_m, double margin_m) {
  std::vector<double> centers;
  for (int i = 0; i < count; ++i) {
    centers.push_back(margin_m + i * (extent_m - 2.0 * margin_m) / (count - 1));
  }
  return centers;
}

// Start coordinates of box rows in [lo, hi]: pairs of rows separated by
// access gaps, the whole pattern centred.
std::vector<double> RowStarts(double lo, double hi, double size_m, double gap_m,
                              double access_gap_m) {
  std::vector<double> starts;
  double y = lo;
  while (y + size_m <= hi) {
    starts.push_back(y);
    y += size_m + (starts.size() % 2 == 1 ? gap_m : access_gap_m);
  }
  if (starts.empty()) return starts;
  const double shift = 0.5 * (hi - (starts.back() + size_m));
  for (double& s : starts) s += shift;
  return starts;
}

}  // namespace

core::Status ZoneAOptions::Validate() const {
  core::Status status = FirstError({
      CheckRange(kZoneAOwner, "width_m", width_m, 20.0, 1000.0),
      CheckRange(kZoneAOwner, "depth_m", depth_m, 20.0, 1000.0),
      CheckRange(kZoneAOwner, "num_lanes_x", num_lanes_x, 2, 50),
      CheckRange(kZoneAOwner, "num_lanes_y", num_lanes_y, 2, 50),
      CheckRange(kZoneAOwner, "lane_width_m", lane_width_m, 2.5, 10.0),
      CheckRange(kZoneAOwner, "wall_to_lane_center_m", wall_to_lane_center_m,
                 0.5 * lane_width_m + 1.0, 50.0),
      CheckRange(kZoneAOwner, "staging_box_width_m", staging_box_width_m, 0.5, 10.0),
      CheckRange(kZoneAOwner, "staging_box_depth_m", staging_box_depth_m, 0.5, 10.0),
      CheckRange(kZoneAOwner, "staging_box_gap_m", staging_box_gap_m, 0.0, 10.0),
      CheckRange(kZoneAOwner, "access_gap_m", access_gap_m, 0.0, 20.0),
      CheckRange(kZoneAOwner, "box_to_lane_m", box_to_lane_m, 1.0, 20.0),
      CheckRange(kZoneAOwner, "pallet_occupancy", pallet_occupancy, 0.0, 1.0),
      CheckRange(kZoneAOwner, "joint_spacing_m", joint_spacing_m, 0.0, 100.0),
      CheckRange(kZoneAOwner, "num_forklifts", num_forklifts, 0, 100),
      CheckRange(kZoneAOwner, "num_pedestrians", num_pedestrians, 0, 100),
  });
  if (!status.ok()) return status;
  const double block_x = (width_m - 2.0 * wall_to_lane_center_m) / (num_lanes_x - 1) -
                         lane_width_m - 2.0 * box_to_lane_m;
  const double block_y = (depth_m - 2.0 * wall_to_lane_center_m) / (num_lanes_y - 1) -
                         lane_width_m - 2.0 * box_to_lane_m;
  if (block_x < staging_box_width_m || block_y < staging_box_depth_m) {
    return core::Status::Error(
        "ZoneAOptions: the blocks between lanes leave no room for a staging box; reduce "
        "num_lanes_x/num_lanes_y or lane_width_m, or enlarge width_m/depth_m");
  }
  return core::Status::Ok();
}

core::Result<World> BuildZoneA(const ZoneAOptions& o) {
  if (core::Status status = o.Validate(); !status.ok()) return status;
  std::mt19937_64 rng(o.seed);
  internal::ZoneBuilder b("zone_a_staging_hub");
  const double W = o.width_m;
  const double D = o.depth_m;
  const double half_lane = 0.5 * o.lane_width_m;

  b.AddWall({-0.15, -0.3}, {-0.15, D + 0.3});
  b.AddWall({W + 0.15, -0.3}, {W + 0.15, D + 0.3});
  b.AddWall({0.0, -0.15}, {W, -0.15});
  b.AddWall({0.0, D + 0.15}, {W, D + 0.15});

  const std::vector<double> xs = LaneCenters(o.num_lanes_x, W, o.wall_to_lane_center_m);
  const std::vector<double> ys = LaneCenters(o.num_lanes_y, D, o.wall_to_lane_center_m);

  // Lanes: the road graph, yellow edge tape and dashed white centre lines
  // between intersections, a zebra crossing in the middle of every x-lane span.
  std::vector<std::vector<int>> node(xs.size(), std::vector<int>(ys.size()));
  for (std::size_t i = 0; i < xs.size(); ++i) {
    for (std::size_t j = 0; j < ys.size(); ++j) node[i][j] = b.AddNode({xs[i], ys[j]});
  }
  for (std::size_t i = 0; i < xs.size(); ++i) {
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      b.AddEdge(node[i][j], node[i][j + 1]);
      const double y0 = ys[j] + half_lane;
      const double y1 = ys[j + 1] - half_lane;
      for (double side : {-half_lane, half_lane}) {
        b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {xs[i] + side, y0},
                  {xs[i] + side, y1}, kTapeWidthM);
      }
      b.AddDashedLine(MarkingColour::kWhite, {xs[i], y0 + 0.5}, {xs[i], y1 - 0.5}, 0.1, 1.0, 1.0);
    }
  }
  for (std::size_t j = 0; j < ys.size(); ++j) {
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
      b.AddEdge(node[i][j], node[i + 1][j]);
      const double x0 = xs[i] + half_lane;
      const double x1 = xs[i + 1] - half_lane;
      for (double side : {-half_lane, half_lane}) {
        b.AddLine(MarkingKind::kTapeSolid, MarkingColour::kYellow, {x0, ys[j] + side},
                  {x1, ys[j] + side}, kTapeWidthM);
      }
      const double xm = 0.5 * (x0 + x1);
      b.AddDashedLine(MarkingColour::kWhite, {x0 + 0.5, ys[j]}, {xm - 2.5, ys[j]}, 0.1, 1.0, 1.0);
      b.AddDashedLine(MarkingColour::kWhite, {xm + 2.5, ys[j]}, {x1 - 0.5, ys[j]}, 0.1, 1.0, 1.0);
      b.AddCrosswalk({xm, ys[j]}, {1.0, 0.0}, 4, 3.0, 0.5, 1.0);
    }
  }

  // Blocks between lanes: columns at the corners, staging boxes, pallet stacks.
  std::bernoulli_distribution occupied(o.pallet_occupancy);
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      const Vector2 lo(xs[i] + half_lane, ys[j] + half_lane);
      const Vector2 hi(xs[i + 1] - half_lane, ys[j + 1] - half_lane);
      for (const Vector2& corner :
           {Vector2(lo.x() + 0.6, lo.y() + 0.6), Vector2(hi.x() - 0.6, lo.y() + 0.6),
            Vector2(lo.x() + 0.6, hi.y() - 0.6), Vector2(hi.x() - 0.6, hi.y() - 0.6)}) {
        b.AddAxisBox(ObstacleKind::kColumn, corner - Vector2(0.25, 0.25),
                     corner + Vector2(0.25, 0.25));
      }
      const double bw = o.staging_box_width_m;
      const double bd = o.staging_box_depth_m;
      const double gap = o.staging_box_gap_m;
      const int num_cols = static_cast<int>(
          std::floor((hi.x() - lo.x() - 2.0 * o.box_to_lane_m + gap) / (bw + gap)));
      const double x_start = 0.5 * (lo.x() + hi.x()) - 0.5 * (num_cols * (bw + gap) - gap);
      for (double y :
           RowStarts(lo.y() + o.box_to_lane_m, hi.y() - o.box_to_lane_m, bd, gap, o.access_gap_m)) {
        for (int c = 0; c < num_cols; ++c) {
          const Vector2 box_lo(x_start + c * (bw + gap), y);
          const Vector2 box_hi = box_lo + Vector2(bw, bd);
          b.AddStagingBox(box_lo, box_hi, MarkingColour::kWhite, kTapeWidthM);
          if (!occupied(rng)) continue;
          // One draw per statement, last first (core::DrawVector's order).
          const double jitter_y = internal::Uniform(&rng, -0.08, 0.08);
          const Vector2 jitter(internal::Uniform(&rng, -0.08, 0.08), jitter_y);
          const double height_m = internal::Uniform(&rng, 0.8, 2.2);
          const double yaw_rad = internal::Uniform(&rng, -0.05, 0.05);
          b.AddPalletStack(0.5 * (box_lo + box_hi) + jitter, {1.0, 1.2}, yaw_rad, height_m);
        }
      }
    }
  }

  if (o.joint_spacing_m > 0.0) {
    for (double x = o.joint_spacing_m; x < W; x += o.joint_spacing_m) b.AddJoint({x, 0}, {x, D});
    for (double y = o.joint_spacing_m; y < D; y += o.joint_spacing_m) b.AddJoint({0, y}, {W, y});
  }

  b.AddMovingObstacles(MovingKind::kForklift, o.num_forklifts, 1.0, &rng);
  // Half the pedestrians walk along the lanes, half over the zebra crossings.
  const int on_lanes = o.num_pedestrians / 2;
  b.AddMovingObstacles(MovingKind::kPedestrian, on_lanes, 1.6, &rng);
  for (int k = on_lanes; k < o.num_pedestrians; ++k) {
    const std::size_t i = std::uniform_int_distribution<std::size_t>(0, xs.size() - 2)(rng);
    const std::size_t j = std::uniform_int_distribution<std::size_t>(0, ys.size() - 1)(rng);
    MovingObstacle walker;
    walker.kind = MovingKind::kPedestrian;
    walker.radius_m = 0.2;
    walker.z_max_m = 1.8;
    walker.reflectivity = 0.3;
    const double xm = 0.5 * (xs[i] + xs[i + 1]) + internal::Uniform(&rng, -1.0, 1.0);
    walker.path_m = {{xm, ys[j] - half_lane - 0.5}, {xm, ys[j] + half_lane + 0.5}};
    walker.speed_mps = internal::Uniform(&rng, 0.8, 1.4);
    walker.phase_m = internal::Uniform(&rng, 0.0, 10.0);
    b.world().moving.push_back(walker);
  }
  return b.Finish({-0.3, -0.3}, {W + 0.3, D + 0.3});
}

}  // namespace groundline::sim
