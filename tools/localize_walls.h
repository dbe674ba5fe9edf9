// LiDAR wall lines in `groundline localize --mode lines --lidar` (on by
// default, --no-wall-lines turns them off; without wall faces for the
// dataset the run warns and goes on without them): the atlas gets the dataset's
// wall faces as kWall lines, and each keyframe gets the straight faces of
// the scan nearest its stamp (localization/lidar/wall_lines.h), deskewed to
// the keyframe by the odometry, as line observations next to the floor lines.
//
// Where the wall faces come from: a real site's rack installation drawing;
// on a simulated dataset (manifest provenance generator "groundline sim")
// the simulator's world, rebuilt from the zone and seed in the provenance and
// checked against the dataset's floor map (the same markings, else an error:
// a dataset made from a scenario file with other zone options).
//
// Health: walls observed / used / rejected (outside every gate or ambiguous)
// per keyframe and in summary.json, and with ground truth the residual of
// each associated wall at the true pose (mean, RMS, and its mean
// Mahalanobis square under the wall's own covariance, ~2 when consistent),
// also split into the walls whose offset came from the band's centre (plain
// walls) and from its front (recessed: rack faces).
#ifndef GROUNDLINE_TOOLS_LOCALIZE_WALLS_H_
#define GROUNDLINE_TOOLS_LOCALIZE_WALLS_H_

#include <vector>

#include <nlohmann/json.hpp>

#include "groundline/core/dataset.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/atlas_walls.h"
#include "groundline/localization/floor_association.h"
#include "groundline/localization/lidar/wall_lines.h"
#include "groundline/localization/sliding_window_smoother.h"
#include "localize_lidar.h"

namespace groundline::tools {

// The wall faces of a simulated dataset (see above) as atlas segments.
core::Result<std::vector<localization::WallSegment>> SimulatedWallSegments(
    const core::Dataset& dataset);

class WallLineSource {
 public:
  // atlas: with its kWall lines (only those are used here, for the counts).
  WallLineSource(const core::Dataset& dataset, const localization::Atlas& atlas,
                 const localization::AssociationOptions& association);

  // The wall observations at a keyframe (call after lidar.KeyframeAt(stamp_s));
  // predicted: the smoother's prediction of the keyframe, for the counts.
  std::vector<localization::LineObservation> Observe(const LidarKeyframeSource& lidar,
                                                     double stamp_s,
                                                     const localization::PoseEstimate& predicted,
                                                     nlohmann::ordered_json* health_line);
  nlohmann::ordered_json Summary() const;

 private:
  localization::lidar::WallLineOptions options_;
  localization::Atlas walls_;
  localization::AssociationOptions association_;
  double time_increment_s_ = 0.0;
  core::Trajectory ground_truth_;
  long keyframes_ = 0, observed_ = 0, used_ = 0, rejected_ = 0, ambiguous_ = 0;
  // Of used walls, at the true pose: rho residuals [m], alpha residuals [rad], d2.
  std::vector<double> rho_residual_m_, alpha_residual_rad_, d2_;
  std::vector<bool> recessed_;  // of each: the offset from the band's front
};

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LOCALIZE_WALLS_H_
