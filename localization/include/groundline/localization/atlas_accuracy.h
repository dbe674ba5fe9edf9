// How close a built atlas (a mapping run's) is to a reference atlas (the
// surveyed floor map's, or the simulator's exact one), for `groundline eval
// --atlas`: each built line is paired with the reference line of its family
// (floor marking or wall/rack face) that it is nearest, among those whose
// extents overlap its own, within a gate. Its offset is the distance of its
// middle from the reference line (where it was seen: rho about the map
// origin would add the direction error times the distance from the origin);
// its direction error and its NEES come from perception::LineError(built,
// reference) in the built line's description, weighed by its own covariance. Junctions are paired
// with the nearest reference junction within the gate.
#ifndef GROUNDLINE_LOCALIZATION_ATLAS_ACCURACY_H_
#define GROUNDLINE_LOCALIZATION_ATLAS_ACCURACY_H_

#include "groundline/localization/atlas.h"

namespace groundline::localization {

struct AtlasAccuracyOptions {
  // A built line is paired only within these of a reference line (its
  // middle's offset, its direction).
  double gate_rho_m = 0.30;
  double gate_alpha_rad = 0.035;  // 2 deg
  double gate_junction_m = 0.30;
  // Extents overlap when within this along the line.
  double extent_margin_m = 0.5;
};

struct LandmarkAccuracy {
  int built = 0;
  int paired = 0;
  double median_abs_rho_m = 0.0;      // the middle's offset; junctions: distance
  double median_abs_alpha_rad = 0.0;  // junctions: 0
  double max_abs_rho_m = 0.0;
  // Share of the paired landmarks whose error is inside their reported 3
  // sigma (NEES below the chi-square 99.73 % quantile, 2 dof).
  double within_3_sigma = 0.0;
};

struct AtlasAccuracy {
  LandmarkAccuracy floor_lines;
  LandmarkAccuracy faces;
  LandmarkAccuracy junctions;
};

AtlasAccuracy CompareAtlases(const Atlas& built, const Atlas& reference,
                             const AtlasAccuracyOptions& options = {});

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_ATLAS_ACCURACY_H_
