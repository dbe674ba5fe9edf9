// A planar 2D LiDAR (defaults: SICK TiM571 as in the seed paper, section 6.2:
// 270 deg field of view, 0.33 deg resolution, 25 m range, 15 Hz, mounted at the
// front bumper 0.18 m above the floor), simulated by ray casting against the
// World's obstacles that cross the scan plane and its moving obstacles.
//
// Scan layout (ROS sensor_msgs/LaserScan conventions, angles in the LiDAR
// frame, counter-clockwise from its x axis): NumRays() = floor(fov /
// resolution) + 1 rays, ray i at angle_min_rad + i * angle_increment_rad,
// symmetric about the x axis (angle_min_rad = -(NumRays() - 1) * resolution / 2,
// so with an odd count one ray looks straight ahead; the defaults give 819 rays
// over +-134.97 deg). Ray i is measured at stamp_s + i * time_increment_s.
//
// Range encoding (REP-117): a finite range lies in [range_min_m, range_max_m];
// +infinity means no return (nothing within range_max_m, or a dropout);
// -infinity means an object closer than range_min_m. Intensities are
// reflectivity * cos(incidence) in [0, 1], 0 for no return.
//
// Noise: Gaussian range noise (clamped to [range_min_m, range_max_m]) and
// independent dropouts. Scan(…, scan_index) seeds its noise from
// (options.seed, scan_index), so a scan is reproducible and scans may be
// computed in any order or in parallel: PlanarLidar is immutable after
// construction and thread-safe.
//
// Not modelled: the vehicle's own body (it would shadow the rear rays),
// beam divergence and mixed pixels, multi-echo, specular surfaces.
#ifndef GROUNDLINE_SIM_LIDAR_H_
#define GROUNDLINE_SIM_LIDAR_H_

#include <cstdint>
#include <numbers>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/sim/obstacle_index.h"
#include "groundline/sim/world.h"

namespace groundline::sim {

struct LaserScan {
  double stamp_s = 0.0;  // time of ray 0
  double time_increment_s = 0.0;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  std::vector<float> ranges_m;
  std::vector<float> intensities;

  double AngleRad(std::size_t i) const {
    return angle_min_rad + static_cast<double>(i) * angle_increment_rad;
  }
};

struct LidarOptions {
  // Mounting pose in base_link (base_link: drive axle midpoint, on the floor).
  // The default x puts it at the front bumper of a 1.68 m long vehicle whose
  // axle is at its middle.
  core::SE2 T_base_lidar = core::SE2(0.84, 0.0, 0.0);
  double height_m = 0.18;  // scan plane above the floor (assumed level)
  double field_of_view_rad = 270.0 * std::numbers::pi / 180.0;
  double angular_resolution_rad = 0.33 * std::numbers::pi / 180.0;
  double range_min_m = 0.05;
  double range_max_m = 25.0;
  double range_noise_sigma_m = 0.015;
  double dropout_probability = 0.005;
  double rate_hz = 15.0;  // scans per second (and mirror revolutions)
  std::uint64_t seed = 1;
  double grid_cell_size_m = 0.5;  // of the spatial index

  core::Status Validate() const;
  int NumRays() const;
  // Time between rays: one revolution (2 pi) takes 1 / rate_hz.
  double TimeIncrementS() const;
};

class PlanarLidar {
 public:
  // Indexes the world's obstacles that cross the scan plane and copies its
  // moving obstacles. Asserts that options.Validate() is ok.
  PlanarLidar(const World& world, const LidarOptions& options);

  // One scan with the vehicle at T_map_base for all rays (no motion during the
  // sweep), moving obstacles placed at stamp_s.
  LaserScan Scan(const core::SE2& T_map_base, double stamp_s, std::uint64_t scan_index) const;
  // The same with an explicit list of moving obstacles instead of the world's.
  LaserScan Scan(const core::SE2& T_map_base, double stamp_s, std::uint64_t scan_index,
                 const std::vector<MovingObstacle>& moving) const;
  // One scan while the vehicle moves along the trajectory (T_map_base, sorted
  // stamps): ray i is cast from the interpolated pose at its own time, so the
  // scan shows the motion distortion of a real sweeping scanner.
  LaserScan ScanAlong(const core::Trajectory& T_map_base, double stamp_s,
                      std::uint64_t scan_index) const;

  const LidarOptions& options() const { return options_; }

 private:
  template <typename PoseOfRay>
  LaserScan Cast(const PoseOfRay& pose_of_ray, double stamp_s, std::uint64_t scan_index,
                 const std::vector<MovingObstacle>& moving) const;

  LidarOptions options_;
  ObstacleIndex index_;
  std::vector<double> reflectivity_;  // per World obstacle
  std::vector<MovingObstacle> moving_;
};

// Scans at options.rate_hz from the trajectory's first stamp to its last, each
// cast with ScanAlong; scan k has scan_index k.
std::vector<LaserScan> SimulateScans(const PlanarLidar& lidar, const core::Trajectory& T_map_base);

// InterpolatePose (world.h) samples trajectories at ray and frame stamps.

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_LIDAR_H_
