// Along-track aliasing of a scan: does the scan look the same after a shift
// of a metre or more along a direction? The Fisher information of a match
// (match_information.h) is local: in a rack aisle the gaps between the
// pallets and the sides of the uprights constrain the along-aisle
// translation within +-half a bay, so the information is full rank, yet the
// aisle repeats every bay (and a smooth corridor at every shift), and a
// match that starts a bay off locks onto the wrong bay. This check sees that
// periodicity.
//
// Self-similarity: the scan's points are rasterized into cells of
// resolution_m (each point also marks its 8 neighbours, tolerating range
// noise and the pallets' set-back); for shifts s along `direction` with
// min_shift_m <= |s| <= max_shift_m (steps of resolution_m) the score is
// the fraction of points p + s * direction that land on a marked cell. The
// scan is aliased along `direction` when the best score reaches
// min_score_ratio (the score at s = 0 is 1).
//
// Pure and thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_SCAN_ALIASING_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_SCAN_ALIASING_H_

#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/lidar/match_information.h"
#include "groundline/localization/lidar/scan_points.h"

namespace groundline::localization::lidar {

struct ScanAliasingOptions {
  double resolution_m = 0.05;
  double min_shift_m = 0.8;
  double max_shift_m = 3.0;
  // Simulated zone B (seed 5): deep-aisle scans score 0.65 median (5 % below
  // 0.40), the open zone A at most 0.21.
  double min_score_ratio = 0.35;
  int min_points = 20;  // fewer points: not checked (not aliased)

  core::Status Validate() const;
};

struct ScanAliasing {
  bool aliased = false;
  core::Vector2 direction = core::Vector2::UnitX();  // unit, base frame
  double best_score = 0.0;                           // in [0, 1]
  double best_shift_m = 0.0;
};

ScanAliasing DetectScanAliasing(const std::vector<ScanPoint>& points,
                                const core::Vector2& direction, const ScanAliasingOptions& options);

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
