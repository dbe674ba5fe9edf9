// Tentative landmarks of mapping mode: observations that match no atlas line
// (junction) are tracked in the map frame across keyframes, and become atlas
// landmarks only after min_keyframes consistent sightings (a stain or a
// shadow seen once does not enter the map).
//
// A track holds its estimate in the map frame with a covariance fused
// (information-weighted, first order) from the sightings, each mapped through
// the keyframe's predicted pose with the pose covariance added. A sighting
// joins the nearest track within gate_chi2 (Mahalanobis, joint covariance);
// a track not seen for more than max_gap_keyframes is dropped.
//
// Not thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LANDMARK_TRACKER_H_
#define GROUNDLINE_LOCALIZATION_LANDMARK_TRACKER_H_

#include <vector>

#include "groundline/core/se2.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_observation.h"

namespace groundline::localization {

struct LandmarkTrackerOptions {
  int min_keyframes = 5;
  int max_gap_keyframes = 3;
  double gate_chi2 = 9.21;
};

class LandmarkTracker {
 public:
  explicit LandmarkTracker(const LandmarkTrackerOptions& options) : options_(options) {}

  // Feeds the unmatched observations of keyframe `keyframe_index` (strictly
  // increasing). Returns the tracks confirmed by this call as new landmarks
  // (ids left 0 for the caller to assign) with the index of the observation
  // that confirmed each.
  struct Confirmed {
    std::vector<std::pair<AtlasLine, int>> lines;
    std::vector<std::pair<AtlasJunction, int>> junctions;
  };
  Confirmed Update(long keyframe_index, const core::SE2& T_map_base,
                   const core::Matrix3& pose_covariance,
                   const std::vector<const LineObservation*>& lines,
                   const std::vector<const JunctionObservation*>& junctions);

  size_t NumTracks() const { return lines_.size() + junctions_.size(); }

 private:
  struct LineTrack {
    AtlasLine estimate;
    int sightings = 0;
    long last_keyframe = 0;
  };
  struct JunctionTrack {
    AtlasJunction estimate;
    int sightings = 0;
    long last_keyframe = 0;
  };

  LandmarkTrackerOptions options_;
  std::vector<LineTrack> lines_;
  std::vector<JunctionTrack> junctions_;
};

// Information-weighted fusion of two estimates x (cov P) and z (cov R) with
// innovation nu = z - x: x += P (P + R)^-1 nu, P -= P (P + R)^-1 P.
void FuseGaussian2(const Eigen::Vector2d& innovation, const Eigen::Matrix2d& R, Eigen::Vector2d* x,
                   Eigen::Matrix2d* P);

// The observation mapped into the map frame, with the pose covariance
// propagated into the line covariance (first order).
AtlasLine LineInMap(const LineObservation& observation, const core::SE2& T_map_base,
                    const core::Matrix3& pose_covariance);
// Moves the nearer end of the line's extent out to the projection of
// point_m if that lies beyond it.
void ExtendLineExtent(const Eigen::Vector2d& point_m, AtlasLine* line);
// Fuses a sighting (LineInMap) into a landmark's estimate and covariance
// (FuseGaussian2 in the estimate's description), and extends its extent.
void FuseLineSighting(const AtlasLine& seen, AtlasLine* estimate);
AtlasJunction JunctionInMap(const JunctionObservation& observation, const core::SE2& T_map_base,
                            const core::Matrix3& pose_covariance);
// Fuses a sighting (JunctionInMap) into a junction's estimate and covariance.
void FuseJunctionSighting(const AtlasJunction& seen, AtlasJunction* estimate);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_LANDMARK_TRACKER_H_
