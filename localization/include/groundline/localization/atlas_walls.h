// Wall lines in the atlas: the straight vertical faces (rack faces, building
// walls) a planar LiDAR sees, surveyed like the floor markings (a site's rack
// installation drawing; on simulated datasets sim/wall_faces.h). They are
// AtlasLines of kind core::MarkingKind::kWall (solid faces) or kRackFace
// (upright fronts with loads set back), which associate only with LiDAR
// face observations (lidar/wall_lines.h, floor_association.h).
#ifndef GROUNDLINE_LOCALIZATION_ATLAS_WALLS_H_
#define GROUNDLINE_LOCALIZATION_ATLAS_WALLS_H_

#include <Eigen/Core>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/localization/atlas.h"

namespace groundline::localization {

struct WallSegment {
  Eigen::Vector2d a_m = Eigen::Vector2d::Zero();  // map frame
  Eigen::Vector2d b_m = Eigen::Vector2d::Zero();
  // Upright fronts with the loads set back behind them (kRackFace), not a
  // solid face (kWall).
  bool rack_face = false;
};

struct AtlasWallOptions {
  // Survey accuracy of a face: a shift across it and a turn about its midpoint.
  double rho_sigma_m = 0.005;
  double alpha_sigma_rad = 0.002;

  core::Status Validate() const;
};

// Appends one kWall or kRackFace line per segment (ids continue after the largest line id
// already in the atlas). Fails, leaving the atlas unchanged, for a segment
// shorter than 1 mm (named by index).
core::Status AppendWallLines(const std::vector<WallSegment>& segments,
                             const AtlasWallOptions& options, Atlas* atlas);

// The number of face lines (kWall and kRackFace) in the atlas.
int CountWallLines(const Atlas& atlas);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_ATLAS_WALLS_H_
