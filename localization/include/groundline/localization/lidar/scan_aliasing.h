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
// carries no evidence either way. The consistent share of a shift is
// consistent / (consistent + contradicted) weight (1 with no evidence).
//
// The scan is aliased along d when the best shift's consistent share reaches
// min_consistent_share. Simulated 1.2 km runs (seed 11, every 8th scan): a
// deep zone-B aisle scores 1.0 (median) and 0.54 (5 %); its low scores are
// scans that see the aisle's end ahead within the 25 m range, which does fix
// the along-aisle position. Open floor (zone A) scores 0.19 (median), 0.57
// (95 %): its staging boxes repeat every 1.7 m, half of them empty; docks
// (zone C) 0.06 and 0.41. At 0.6, 93 % of the deep-aisle scans (all of those
// whose aisle end is beyond the range), 4 % of zone A's and 0.6 % of zone C's
// are aliased. The plain self-similarity this replaces (the share of all
// points landing on the scan after a shift, aliased from 0.35) flagged 57 %
// of zone A and 74 % of zone C: walls and rack faces parallel to d are
// consistent with every shift.
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
  int min_points = 20;  // fewer points: not checked (not aliased)

  core::Status Validate() const;
};

struct ScanAliasing {
  bool aliased = false;
  core::Vector2 direction = core::Vector2::UnitX();  // unit, base frame
  double best_score = 0.0;                           // the best shift's consistent share, in [0, 1]
  double best_shift_m = 0.0;
  // Consistent + contradicted weight at the best shift (in points along d).
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
