// Free-space consistency of a loop-closure candidate: before a loop match
// enters the pose graph, the scan, placed at the matched pose in the
// submap, must not contradict what the submap knows about free space.
//
// A correlative score only looks at where the returns land. A wrong match
// in a self-similar place (a corridor shifted by a door spacing, the next
// aisle) can put most returns on occupied cells while its rays cross walls
// the submap has seen, or its returns fall where the submap has seen
// through. For each of up to max_rays returns (evenly subsampled) at
// T_grid_base:
//   - a return is "in free space" when its cell and the 8 neighbours are
//     known with P < free_probability (ProbabilityGrid::IsFreeAround);
//   - a ray "crosses an occupied cell" when a cell of its Bresenham line
//     from the sensor has P >= occupied_probability; a return's line stops
//     where it is ray_end_margin_m from the surface it ends on, i.e.
//     ray_end_margin_m / max(0.2, |cos incidence|) short of the return
//     (incidence on the surface normal of scan_points.h): the margin
//     absorbs the match error and the thickness of a mapped wall, which a
//     grazing ray runs along for longer. A return without a normal (far,
//     isolated; its incidence is unknown) is not traced, only tested for
//     free space.
// No-return rays are not used: glass, black surfaces and dropouts give no
// return where a submap has walls (on MIT CSAIL they put 20-25 % of the
// beams of true revisits through occupied cells).
// A return with either is a violation; the candidate is consistent when the
// violating fraction is at most max_violation_fraction. Moved pallets and
// passing forklifts make a few returns violate at a true revisit; the
// fraction, not a count, keeps them from vetoing it.
//
// Cost: O(max_rays * ray length / resolution) grid reads.
// Pure and thread-safe given a const grid.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_LOOP_VERIFICATION_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_LOOP_VERIFICATION_H_

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/lidar/probability_grid.h"
#include "groundline/localization/lidar/scan_points.h"

namespace groundline::localization::lidar {

struct FreeSpaceCheckOptions {
  double free_probability = 0.35;      // below: known free
  double occupied_probability = 0.65;  // at or above: known occupied
  double ray_end_margin_m = 0.2;
  int max_rays = 120;
  // On MIT CSAIL, loop matches that the solved graph later disagreed with
  // by > 15 cm were 7 % of those below 0.05 and 64 % of those in
  // [0.15, 0.2); at 0.15 the check also dropped true revisits that ACES
  // needs (docs/lidar_slam.md).
  double max_violation_fraction = 0.2;

  core::Status Validate() const;
};

struct FreeSpaceCheck {
  int rays = 0;                   // returns checked
  int returns_in_free = 0;        // returns on known free space
  int rays_through_occupied = 0;  // their rays crossing a known occupied cell
  int violations = 0;             // returns with either
  double violation_fraction = 0.0;
  bool consistent = true;
};

// The scan's returns (base frame, from scan.sensor_origin_m) at T_grid_base
// in `grid`. A scan without returns is consistent (nothing contradicts).
FreeSpaceCheck CheckFreeSpace(const ProbabilityGrid& grid, const ScanPoints& scan,
                              const core::SE2& T_grid_base, const FreeSpaceCheckOptions& options);

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_LOOP_VERIFICATION_H_
