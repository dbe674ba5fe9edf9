// Aisle exits: the moments a vehicle leaves an aisle, and the position error
// of an estimate there (issue 6: "no aisle exit with an error above 5 cm" in
// zone B, where along-track drift builds up over an 85 m aisle and the
// transverse markings at its end must catch it).
//
// Definitions (derived in docs/metrics.md, "Aisle exits"):
// - An aisle is the strip between two parallel straight solid tapes of the
//   floor map (kTapeSolid, two-vertex polylines) each at least
//   min_length_m long, min_width_m..max_width_m apart (centre to centre) and
//   overlapping along their length by at least min_overlap_share of the
//   shorter: the rectangle centred between them over the overlap. In zone B
//   these are the 32 rack aisles (85 m, tapes 2.1 m apart); zone D's
//   corridors with two boundary lines count too.
// - An aisle exit is a ground-truth sample that lies outside an aisle's
//   rectangle while the previous one was inside, after the vehicle travelled
//   at least min_inside_m inside it (a crossing of a cross aisle is not an
//   exit). Its stamp is that first sample outside.
// - The exit error is |p_est - p_ref| at that stamp, the estimate
//   interpolated between its poses (trajectory_association.h, kInterpolate;
//   exits with no estimate pose within max_gap_s on both sides are
//   unmatched).
//
// Pure functions; thread-safe.
#ifndef GROUNDLINE_CORE_AISLE_EXITS_H_
#define GROUNDLINE_CORE_AISLE_EXITS_H_

#include <cstddef>
#include <vector>

#include "groundline/core/floor_map.h"
#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/core/trajectory_metrics.h"

namespace groundline::core {

struct AisleExitOptions {
  double min_length_m = 20.0;
  double min_width_m = 1.0;
  double max_width_m = 4.0;
  double max_angle_rad = 0.01;  // "parallel"
  double min_overlap_share = 0.8;
  double min_inside_m = 10.0;
  double max_gap_s = 1.0;           // interpolation of the estimate at the exit stamp
  double error_threshold_m = 0.05;  // exits above it are counted
  Status Validate() const;
};

// The strip from start_m to end_m (centre line), half_width_m to either side.
struct Aisle {
  Vector2 start_m = Vector2::Zero();
  Vector2 end_m = Vector2::Zero();
  double half_width_m = 0.0;
  bool Contains(const Vector2& p_m) const;
};
std::vector<Aisle> FindAisles(const FloorMap& map, const AisleExitOptions& options);

struct AisleExit {
  double stamp_s = 0.0;
  std::size_t aisle = 0;  // index into the aisles given
};
// `reference` sorted by stamp.
std::vector<AisleExit> FindAisleExits(const Trajectory& reference, const std::vector<Aisle>& aisles,
                                      const AisleExitOptions& options);

struct AisleExitSummary {
  std::size_t n_exits = 0;      // exits of the reference
  std::size_t n_unmatched = 0;  // exits without an estimate around them
  ErrorStats error_m;           // over the matched exits
  std::size_t n_above_threshold = 0;
};
// Exits of `reference` from the aisles of `map`, and the estimate's error
// there. Errors on invalid options or an empty / unsorted trajectory; a map
// without aisles gives n_exits = 0.
Result<AisleExitSummary> ComputeAisleExitErrors(const Trajectory& estimate,
                                                const Trajectory& reference, const FloorMap& map,
                                                const AisleExitOptions& options = {});

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_AISLE_EXITS_H_
