// The straight vertical faces of a World that a planar LiDAR sees as lines
// (rack faces, building walls): the "installation drawing" of the site from
// which the atlas takes its wall lines (localization/atlas_walls.h), as the
// floor map is the survey of the floor markings.
//
// Structure only: the faces of walls, columns, rack uprights and closed dock
// doors; pallets, loads and trailers move and are not part of the drawing
// (they still hide faces). A rack face is the line of its upright fronts: the
// uprights every upright_pitch_m with the loads set back behind them.
//
// Method. Each edge of a structural footprint that crosses the scan plane is
// sampled every sample_step_m; a sample is visible when the disc of
// clearance_radius_m centred clearance_offset_m in front of it (outward
// normal) holds no obstacle of the scan plane, i.e. there is open floor in
// front of the face (an aisle, not a 0.2 m flue or the gap to a wall).
// Visible pieces that are collinear (same outward normal, offsets within
// merge_offset_m) and no more than max_gap_m apart along the line are merged
// when the gap is backed: on at least min_backed_fraction of it an obstacle
// stands within max_setback_m behind the face line (the loads between rack
// uprights), so that the LiDAR sees the face's band there and not an opening
// (a row end, whose loads start 0.3 m in, is not a face). A face merged
// across a gap where the face line itself is open (the loads at least
// min_recess_m behind it) is a rack face; otherwise it is solid (a wall seen
// in pieces past things in front of it). Merged faces shorter than
// min_length_m are dropped.
//
// Frames and units: map frame, metres. Pure function; thread-safe.
#ifndef GROUNDLINE_SIM_WALL_FACES_H_
#define GROUNDLINE_SIM_WALL_FACES_H_

#include <vector>

#include "groundline/core/status.h"
#include "groundline/sim/world.h"

namespace groundline::sim {

struct WallFace {
  Vector2 a_m = Vector2::Zero();
  Vector2 b_m = Vector2::Zero();
  Vector2 outward_normal = Vector2::UnitX();  // unit, towards the open floor
  // Merged across a recessed gap (the loads at least min_recess_m behind the
  // face line): a rack face, which the LiDAR sees as a recessed band.
  bool rack_face = false;
};

struct WallFaceOptions {
  double plane_height_m = 0.18;  // the LiDAR's scan plane
  double sample_step_m = 0.05;
  double clearance_offset_m = 0.6;
  double clearance_radius_m = 0.55;
  double merge_offset_m = 0.002;
  double max_gap_m = 3.0;
  double max_setback_m = 0.08;
  double min_backed_fraction = 0.5;
  double min_recess_m = 0.01;
  double min_length_m = 3.0;

  core::Status Validate() const;
};

// Faces sorted by (outward normal angle, offset, start); asserts valid options.
std::vector<WallFace> WallFaces(const World& world, const WallFaceOptions& options);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_WALL_FACES_H_
