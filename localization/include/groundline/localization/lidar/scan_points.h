// A planar LiDAR scan as points in the robot (base) frame, with the local
// surface normal of each point where the scan shows a straight surface.
//
// Points come from ranges: p_base = T_base_laser * (r cos a, r sin a). Ranges
// outside [min_range_m, max_range_m] are dropped; a "no return" beam (range
// at or above the sensor's max) becomes a free-space end point at
// missing_ray_length_m instead (it clears space but is never matched).
//
// Normals: PCA of the neighbours within normal_radius_m among the
// neighbour_beams beams on either side (in beam order); a point gets a normal
// when at least 3 neighbours lie on a line (smallest / largest eigenvalue of
// their scatter below max_planarity). The normal points towards the sensor.
// A voxel filter then keeps the first point of each voxel_size_m square.
//
// Pure functions; thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_SCAN_POINTS_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_SCAN_POINTS_H_

#include <span>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::localization::lidar {

struct ScanPoint {
  core::Vector2 point_m;                         // base frame
  core::Vector2 normal = core::Vector2::Zero();  // unit, base frame; zero if none
  bool has_normal() const { return normal.squaredNorm() > 0.5; }
};

struct ScanPoints {
  core::Vector2 sensor_origin_m = core::Vector2::Zero();  // base frame
  std::vector<ScanPoint> points;                          // returns, voxel-filtered, beam order
  std::vector<core::Vector2> misses_m;                    // end points of no-return rays
};

struct ScanPointsOptions {
  double min_range_m = 0.1;
  double max_range_m = 30.0;
  // No-return rays clear free space up to this length (0: not at all).
  double missing_ray_length_m = 5.0;
  double voxel_size_m = 0.05;
  int neighbour_beams = 3;
  double normal_radius_m = 0.3;
  double max_planarity = 0.05;

  core::Status Validate() const;
};

// ranges_m[i] at angle_min_rad + i * angle_increment_rad in the laser frame;
// sensor_max_range_m: ranges at or above it mean "no return".
ScanPoints ScanPointsFromRanges(const std::vector<double>& ranges_m, double angle_min_rad,
                                double angle_increment_rad, double sensor_max_range_m,
                                const core::SE2& T_base_laser, const ScanPointsOptions& options);

// The same for a laser that moves during its sweep (deskewing): beam i is
// measured from T_base_laser_of_beam[i], the laser's pose at that beam's time
// in the base frame of the instant the scan describes (one pose per range;
// an empty span: T_base_laser for every beam). T_base_laser is the laser's
// pose at that instant (sensor_origin_m).
ScanPoints ScanPointsFromRanges(const std::vector<double>& ranges_m, double angle_min_rad,
                                double angle_increment_rad, double sensor_max_range_m,
                                const core::SE2& T_base_laser,
                                std::span<const core::SE2> T_base_laser_of_beam,
                                const ScanPointsOptions& options);

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_SCAN_POINTS_H_
