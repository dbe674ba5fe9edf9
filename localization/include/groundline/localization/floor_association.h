// Data association of floor observations with the atlas: each observed line
// (junction) against every atlas line (junction) by the Mahalanobis distance
// of the innovation under the joint covariance
//
//   nu = LineDifference(l_pred, z),  l_pred = InverseTransformLine(T_map_base, l_map)
//   S  = Sigma_z + J_T Sigma_T J_T^T + J_l Sigma_l J_l^T,   d2 = nu^T S^-1 nu
//
// (Sigma_T: the predicted pose covariance, tangent space; Sigma_l: the atlas
// line's). A pair is a candidate when d2 <= gate_chi2 (chi-square, 2 dof;
// 9.21 is the 0.99 quantile) and, for lines, the observed extent overlaps the
// atlas segment (projected on the atlas line, extended by extent_margin_m):
// collinear markings far apart along an aisle are different landmarks, and
// the kinds are compatible (KindsCompatible: walls only with walls).
// The nearest candidate wins unless a second candidate is within
// ambiguity_margin_chi2 of it; then the observation is rejected as ambiguous
// (unless the two are duplicates of one marking, see the options).
// Several observations may match one atlas line (a tape seen in two pieces).
//
// Pure functions; thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_FLOOR_ASSOCIATION_H_
#define GROUNDLINE_LOCALIZATION_FLOOR_ASSOCIATION_H_

#include <limits>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_observation.h"

namespace groundline::localization {

struct AssociationOptions {
  double gate_chi2 = 9.21;
  double ambiguity_margin_chi2 = 4.0;
  double extent_margin_m = 0.5;
  // Two landmarks closer than this (rho and alpha of LineDifference; point
  // distance for junctions) are duplicates of one marking, not an ambiguity.
  double duplicate_rho_m = 0.02;
  double duplicate_alpha_rad = 0.01;

  core::Status Validate() const;
};

struct Match {
  int observation = 0;
  int landmark = -1;  // index into the atlas' lines / junctions; -1 if none
  double mahalanobis2 = 0.0;
  bool ambiguous = false;  // rejected because two landmarks fit
  // The smallest d2 to any compatible landmark, inside the gate or not
  // (infinite when none is compatible): how new an unmatched observation is.
  double nearest_mahalanobis2 = std::numeric_limits<double>::infinity();
};

// d2 of one line observation against one atlas line (no extent check).
double LineMahalanobis2(const LineObservation& observation, const AtlasLine& landmark,
                        const core::SE2& T_map_base, const core::Matrix3& pose_covariance);

// d2 of one junction observation against one atlas junction.
double JunctionMahalanobis2(const JunctionObservation& observation, const AtlasJunction& landmark,
                            const core::SE2& T_map_base, const core::Matrix3& pose_covariance);

// True if the observed extent, mapped by T_map_base, overlaps the landmark's
// segment extended by margin_m at both ends.
bool ExtentsOverlap(const LineObservation& observation, const AtlasLine& landmark,
                    const core::SE2& T_map_base, double margin_m);
// The same for two landmarks: a's extent against b's, along b's direction.
bool ExtentsOverlap(const AtlasLine& a, const AtlasLine& b, double margin_m);

// A LiDAR face observation may match only a face landmark (kWall or
// kRackFace), a floor-marking observation only a floor-marking landmark: a
// rack face and the aisle tape beside it are parallel and a few centimetres
// apart. A face observation matches only a face of its own kind: a recessed
// band (kRackFace: its offset taken from its front) on a solid face is two
// faces at different depths (zone C's dock wall and its doors 10 cm behind)
// whose front came out 2-3 cm off at the true pose; a plain band (kWall) on
// a rack face is the loads alone, 5 cm behind the uprights, or a mix (zone
// B: 12.5 mm RMS at the true pose, against 1.5-2.3 mm on solid walls).
bool KindsCompatible(core::MarkingKind observed, core::MarkingKind landmark);

// One Match per observation, in order. excluded (when given, parallel to the
// atlas' lines / junctions): landmarks flagged true are no candidates (the
// retired ones of the atlas upkeep).
std::vector<Match> AssociateLines(const std::vector<LineObservation>& observations,
                                  const Atlas& atlas, const core::SE2& T_map_base,
                                  const core::Matrix3& pose_covariance,
                                  const AssociationOptions& options,
                                  const std::vector<bool>* excluded = nullptr);
std::vector<Match> AssociateJunctions(const std::vector<JunctionObservation>& observations,
                                      const Atlas& atlas, const core::SE2& T_map_base,
                                      const core::Matrix3& pose_covariance,
                                      const AssociationOptions& options,
                                      const std::vector<bool>* excluded = nullptr);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_FLOOR_ASSOCIATION_H_
