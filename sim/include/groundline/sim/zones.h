// The four zone presets of the 24,000 m^2 logistics terminal (seed paper,
// section 6.1), generated from parameters. Each Build* returns a World whose
// map frame has its origin at the zone's south-west inner wall corner, x east,
// y north. The same options and seed always give the same World.
//
// What the planar LiDAR (0.18 m above the floor) sees in each zone:
// - A: walls, building columns, pallet stacks in the staging boxes (placed by
//   the seed, so they move between runs), forklifts and pedestrians.
// - B: the rack uprights (full height) at a regular pitch and the ground-level
//   pallet loads set back behind them. Beams start at first_beam_height_m
//   (1.5 m) and are invisible to the scan plane. With pallet_fill = 1 every bay
//   is identical, so an aisle is periodic along its axis with the upright
//   pitch: the LiDAR-degenerate case. pallet_fill < 1 breaks the symmetry.
// - C: the dock wall, closed doors, the walls of docked trailers, columns,
//   pallet stacks in staging lanes, forklifts and pedestrians.
// - D: long smooth walls and the openings of the cross corridors, nothing else.
#ifndef GROUNDLINE_SIM_ZONES_H_
#define GROUNDLINE_SIM_ZONES_H_

#include <cstdint>
#include <string_view>

#include "groundline/core/status.h"
#include "groundline/sim/world.h"

namespace groundline::sim {

// Zone A, open inbound staging hub (~6,500 m^2): a grid of 4 m lanes (yellow
// edges, dashed white centre lines, zebra crossings) between blocks of white
// staging boxes, pallet stacks in a random subset of boxes, columns at the
// block corners, a 6 m grid of saw-cut joints.
struct ZoneAOptions {
  std::uint64_t seed = 1;
  double width_m = 100.0;  // x
  double depth_m = 65.0;   // y
  int num_lanes_x = 4;     // lanes running along y, spread over the width
  int num_lanes_y = 3;     // lanes running along x, spread over the depth
  double lane_width_m = 4.0;
  double wall_to_lane_center_m = 4.0;
  double staging_box_width_m = 1.4;  // x
  double staging_box_depth_m = 1.6;  // y
  double staging_box_gap_m = 0.3;
  double access_gap_m = 3.0;      // between pairs of box rows
  double box_to_lane_m = 1.2;     // lane edge to the first box
  double pallet_occupancy = 0.5;  // probability that a box holds a stack
  double joint_spacing_m = 6.0;   // 0: no joints
  int num_forklifts = 4;
  int num_pedestrians = 6;

  core::Status Validate() const;
};

// Zone B, high-bay racks: num_aisles parallel aisles along y between rack rows
// (single rows against the side walls, back-to-back double rows between
// aisles), cross-aisles at both ends, yellow boundary tape along both sides of
// each aisle, white stop bars at the aisle ends, transverse expansion joints
// across the whole floor at joint_spacing_m.
struct ZoneBOptions {
  std::uint64_t seed = 1;
  int num_aisles = 32;
  double aisle_length_m = 85.0;       // rack run along the aisle
  double aisle_clear_width_m = 2.25;  // between facing upright faces
  double upright_pitch_m = 2.7;
  double upright_width_m = 0.10;  // along the aisle
  double upright_depth_m = 0.08;  // across the aisle
  double rack_depth_m = 1.1;
  double flue_gap_m = 0.2;  // between back-to-back rows
  double wall_gap_m = 0.2;  // between a single row and the side wall
  double cross_aisle_width_m = 4.0;
  double first_beam_height_m = 1.5;
  double rack_height_m = 9.5;
  int pallets_per_bay = 2;
  double pallet_width_m = 1.0;  // along the aisle
  double pallet_depth_m = 1.0;
  double pallet_height_m = 1.35;   // pallet plus load, ground level
  double pallet_setback_m = 0.05;  // pallet face behind the upright face
  double pallet_fill = 1.0;        // probability that a ground slot is full
  double tape_offset_m = 0.10;     // rack face to tape centre line
  double stop_bar_width_m = 0.2;
  double stop_bar_inset_m = 0.5;  // aisle end to stop bar centre line
  double joint_spacing_m = 6.0;   // 0: no joints
  int num_pedestrians = 2;

  core::Status Validate() const;
  // Distance between the centre lines of neighbouring aisles.
  double AislePitchM() const { return aisle_clear_width_m + 2.0 * rack_depth_m + flue_gap_m; }
  // Centre line x of aisle i (0-based) and the y range of the rack run.
  double AisleCenterXM(int i) const;
  double RackStartYM() const { return cross_aisle_width_m; }
};

// Zone C, loading docks (~4,500 m^2): num_doors roll-up doors in the north wall
// in groups, each door open (possibly with a docked trailer) or closed by the
// seed; an apron lane along the doors, a main lane along the south wall, 4 m
// connectors between the door groups; worn yellow lane tape, two rows of white
// staging lanes in front of every door, stop bars before the doors.
struct ZoneCOptions {
  std::uint64_t seed = 1;
  int num_doors = 16;
  int doors_per_group = 4;
  double door_width_m = 3.0;
  double door_pitch_m = 4.5;
  double group_gap_m = 5.0;
  double end_margin_m = 6.0;
  double depth_m = 45.0;
  double lane_width_m = 4.0;
  double main_lane_center_y_m = 6.0;
  double apron_lane_from_wall_m = 4.5;  // dock wall to apron lane centre
  double staging_lane_width_m = 2.8;
  double staging_lane_length_m = 12.0;
  double door_open_probability = 0.5;
  double trailer_probability = 0.7;  // of an open door
  double pallet_occupancy = 0.4;
  double tape_wear_fraction = 0.4;
  double joint_spacing_m = 6.0;  // 0: no joints
  int num_forklifts = 3;
  int num_pedestrians = 3;

  core::Status Validate() const;
  double WidthM() const;
  double DoorCenterXM(int door) const;
};

// Zone D, inter-bay corridors (~2,000 m^2): two long parallel corridors joined
// by cross corridors, smooth walls, yellow boundary lines along both sides,
// saw-cut joints across every corridor every joint_spacing_m.
struct ZoneDOptions {
  std::uint64_t seed = 1;
  double corridor_length_m = 200.0;
  double corridor_width_m = 4.0;
  double corridor_separation_m = 30.0;  // centre line to centre line
  int num_cross_corridors = 3;
  double joint_spacing_m = 6.0;
  double boundary_line_offset_m = 0.3;  // wall face to line centre
  double boundary_line_width_m = 0.10;
  int num_forklifts = 1;
  int num_pedestrians = 2;

  core::Status Validate() const;
  double CrossCorridorCenterXM(int k) const;
};

core::Result<World> BuildZoneA(const ZoneAOptions& options);
core::Result<World> BuildZoneB(const ZoneBOptions& options);
core::Result<World> BuildZoneC(const ZoneCOptions& options);
core::Result<World> BuildZoneD(const ZoneDOptions& options);

enum class Zone { kA, kB, kC, kD };

// "A".."D" (case-insensitive); an error names the accepted values.
core::Result<Zone> ParseZone(std::string_view name);
// A preset with default options and the given seed.
core::Result<World> BuildZone(Zone zone, std::uint64_t seed);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_ZONES_H_
