// Along-track aliasing of a scan: would the scan, taken from a pose shifted
// by a metre or more along its weakest direction, look the same? The Fisher
// information of a match (match_information.h) is local: in a rack aisle the
// gaps between the pallets and the sides of the uprights constrain the
// along-aisle translation within +-half a bay, so the information is full
// rank, yet the aisle repeats every bay, and a match that starts a bay off
// locks onto the wrong bay. This check sees that periodicity.
//
// Two-view consistency. The scan is rasterized into a local occupancy grid
// of resolution_m: cells within one cell of a return are occupied, cells a
// ray crossed (up to free_stop_m short of its return, and the whole length
// of a no-return ray, scan_points.h's misses) are free, the rest unknown.
// For a shift s along the unit `direction` d (min_shift_m <= s <= max_shift_m,
// steps of resolution_m) the scan is compared with a copy of itself taken s
// further along d, both ways: each point p + s d and p - s d is
//  - consistent when it lands on an occupied cell,
//  - contradicted when it lands on a free cell (the scan sees through it),
//  - unseen otherwise (occluded or out of the field of view: no evidence).
// A point only informs the along-d position through the component of its
// normal along d, so it counts with the weight (n . d)^2 (its share of the
// Fisher information along d; points without a normal count 0). A surface
// parallel to d (a wall, a rack face) is consistent with every shift and
// carries no evidence either way.
//
// One surface is one piece of evidence, not hundreds: its returns share the
// surface's error (where it stands in the world, what stands in front of
// it), as match_information.h caps the points of a whole scan. So the
// points are cut into surfaces (runs of consecutive returns, in beam order,
// less than surface_gap_m apart) and each surface's total weight is capped
// at max_surface_points (its points scaled down alike). This is what tells a
// rack aisle whose end is in range from open floor: in the aisle the only
// evidence against a shift along it is the end face, one surface 7-17 m
// ahead seen through the aisle's mouth (a few dozen returns, few of them
// independent), against the consistent evidence of many uprights and pallet
// sides; on open floor the contradiction comes from many surfaces around.
//
// The consistent share of a shift is consistent / (consistent + contradicted)
// weight (1 with no evidence). The scan is aliased along d when the best
// shift's consistent share reaches min_consistent_share.
//
// Measured on the simulated 1.2 km runs (seed 11; every keyframe of a
// lines+lidar localize run, regions of sim/zone_regions.h with a 5 m end
// margin), share of keyframes aliased, uncapped -> capped at 8 points:
// zone B deep aisle 93.5 % -> 97.4 % (the aisles left unflagged had their
// end 7-17 m ahead), B cross-aisles 40.8 % -> 36.0 %, open floor A 4.0 % ->
// 3.6 % (staging boxes repeating every 1.7 m), docks C 1.1 % -> 1.8 %, zone D
// corridors 77.4 % -> 81.2 %, D junctions 28.5 % -> 35.0 %; the full
// system's ATE (lines + LiDAR + walls) moved by less than 0.01 cm in every
// zone (B 0.73 cm, max 5.14 cm). The plain self-similarity the weighted
// test replaced (the share of all points landing on the scan after a shift,
// aliased from 0.35) flagged 57 % of zone A and 74 % of zone C: walls and
// rack faces parallel to d are consistent with every shift.
//
// Pure and thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_SCAN_ALIASING_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_SCAN_ALIASING_H_

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/lidar/match_information.h"
#include "groundline/localization/lidar/scan_points.h"

namespace groundline::localization::lidar {

struct ScanAliasingOptions {
  double resolution_m = 0.05;
  double min_shift_m = 0.8;
  double max_shift_m = 3.0;
  double free_stop_m = 0.1;  // a ray clears space up to this short of its return
  double min_consistent_share = 0.6;
  // Consecutive returns farther apart than this belong to different surfaces.
  double surface_gap_m = 0.2;
  // A surface's along-d weight is capped at this many points (>= a few
  // hundred: effectively uncapped, the test before the cap).
  double max_surface_points = 8.0;
  int min_points = 20;  // fewer points: not checked (not aliased)

  core::Status Validate() const;
};

struct ScanAliasing {
  bool aliased = false;
  core::Vector2 direction = core::Vector2::UnitX();  // unit, base frame
  double best_score = 0.0;                           // the best shift's consistent share, in [0, 1]
  double best_shift_m = 0.0;
  // Consistent + contradicted weight at the best shift (in points along d,
  // surface-capped).
  double evidence = 0.0;
};

// scan: in the base frame, with normals; the direction checked is
// WeakestTranslation(information).
ScanAliasing DetectScanAliasing(const ScanPoints& scan, const MatchInformation& information,
                                const ScanAliasingOptions& options);

// The translation direction (unit, base frame) a match constrains least: the
// eigenvector of the smallest eigenvalue of the information's translation block.
core::Vector2 WeakestTranslation(const MatchInformation& information);

// The kept information with the translation along `direction` removed
// (projected out), for a match that is aliased along it: S^T S of the result
// is P^T (S^T S) P with P the projector off (direction, 0).
core::Matrix3 RemoveTranslation(const core::Matrix3& sqrt_information,
                                const core::Vector2& direction);

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_SCAN_ALIASING_H_
