#include "groundline/sim/lidar.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <random>

#include "options_check.h"

namespace groundline::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr const char* kLidarOwner = "LidarOptions";

std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// A moving obstacle frozen at the scan's stamp.
struct FrozenObstacle {
  bool circle = false;
  Vector2 center_m = Vector2::Zero();
  double radius_m = 0.0;
  std::array<Vector2, 4> corners;
  double reflectivity = 0.0;
};

}  // namespace

core::Status LidarOptions::Validate() const {
  return internal::FirstError({
      internal::CheckRange(kLidarOwner, "height_m", height_m, 0.0, 10.0),
      internal::CheckRange(kLidarOwner, "field_of_view_rad", field_of_view_rad, 1e-3,
                           2.0 * std::numbers::pi),
      internal::CheckRange(kLidarOwner, "angular_resolution_rad", angular_resolution_rad, 1e-5,
                           field_of_view_rad),
      internal::CheckRange(kLidarOwner, "range_min_m", range_min_m, 0.0, 10.0),
      internal::CheckRange(kLidarOwner, "range_max_m", range_max_m, range_min_m + 0.01, 1000.0),
      internal::CheckRange(kLidarOwner, "range_noise_sigma_m", range_noise_sigma_m, 0.0, 1.0),
      internal::CheckRange(kLidarOwner, "dropout_probability", dropout_probability, 0.0, 1.0),
      internal::CheckRange(kLidarOwner, "rate_hz", rate_hz, 0.1, 1000.0),
      internal::CheckRange(kLidarOwner, "grid_cell_size_m", grid_cell_size_m, 0.05, 50.0),
  });
}

int LidarOptions::NumRays() const {
  return static_cast<int>(std::floor(field_of_view_rad / angular_resolution_rad + 1e-9)) + 1;
}

double LidarOptions::TimeIncrementS() const {
  return angular_resolution_rad / (2.0 * std::numbers::pi * rate_hz);
}

PlanarLidar::PlanarLidar(const World& world, const LidarOptions& options)
    : options_(options),
      index_(world, ObstacleIndex::Options{options.grid_cell_size_m, options.height_m}),
      moving_(world.moving) {
  assert(options.Validate().ok());
  for (const Obstacle& obstacle : world.obstacles) reflectivity_.push_back(obstacle.reflectivity);
}

LaserScan PlanarLidar::Scan(const core::SE2& T_map_base, double stamp_s,
                            std::uint64_t scan_index) const {
  return Scan(T_map_base, stamp_s, scan_index, moving_);
}

LaserScan PlanarLidar::Scan(const core::SE2& T_map_base, double stamp_s, std::uint64_t scan_index,
                            const std::vector<MovingObstacle>& moving) const {
  return Cast([&](int) { return T_map_base; }, stamp_s, scan_index, moving);
}

LaserScan PlanarLidar::ScanAlong(const core::Trajectory& T_map_base, double stamp_s,
                                 std::uint64_t scan_index) const {
  const double dt = options_.TimeIncrementS();
  return Cast([&](int i) { return InterpolatePose(T_map_base, stamp_s + i * dt); }, stamp_s,
              scan_index, moving_);
}

template <typename PoseOfRay>
LaserScan PlanarLidar::Cast(const PoseOfRay& pose_of_ray, double stamp_s, std::uint64_t scan_index,
                            const std::vector<MovingObstacle>& moving) const {
  const LidarOptions& o = options_;
  const int n = o.NumRays();
  LaserScan scan;
  scan.stamp_s = stamp_s;
  scan.time_increment_s = o.TimeIncrementS();
  scan.angle_min_rad = -0.5 * (n - 1) * o.angular_resolution_rad;
  scan.angle_increment_rad = o.angular_resolution_rad;
  scan.range_min_m = o.range_min_m;
  scan.range_max_m = o.range_max_m;
  scan.ranges_m.resize(static_cast<std::size_t>(n));
  scan.intensities.resize(static_cast<std::size_t>(n));

  const Vector2 sensor_m = (pose_of_ray(0) * o.T_base_lidar).translation();
  std::vector<FrozenObstacle> frozen;
  for (const MovingObstacle& m : moving) {
    if (m.z_min_m > o.height_m || m.z_max_m < o.height_m || !m.PresentAt(stamp_s)) continue;
    const OrientedBox box = m.FootprintAt(stamp_s);
    // Generous culling: the vehicle moves a little during the sweep.
    if ((box.center_m - sensor_m).norm() > o.range_max_m + box.BoundingRadius() + 1.0) continue;
    frozen.push_back({m.IsCircle(), box.center_m, m.radius_m, box.Corners(), m.reflectivity});
  }

  std::mt19937_64 rng(SplitMix64(o.seed ^ SplitMix64(scan_index)));
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < n; ++i) {
    const core::SE2 T_map_lidar = pose_of_ray(i) * o.T_base_lidar;
    const double angle = T_map_lidar.yaw() + scan.AngleRad(static_cast<std::size_t>(i));
    const Vector2 origin = T_map_lidar.translation();
    const Vector2 dir(std::cos(angle), std::sin(angle));
    const RayHit hit = index_.CastRay(origin, dir, o.range_max_m);
    double range_m = hit.range_m;
    double reflectivity = hit.hit() ? reflectivity_[static_cast<std::size_t>(hit.obstacle)] : 0.0;
    double cos_incidence = hit.cos_incidence;
    for (const FrozenObstacle& f : frozen) {
      double c = 0.0;
      double t = kInf;
      if (f.circle) {
        t = IntersectRayCircle(origin, dir, f.center_m, f.radius_m, &c);
      } else {
        for (int k = 0; k < 4; ++k) {
          double ck = 0.0;
          const double tk =
              IntersectRaySegment(origin, dir, f.corners[static_cast<std::size_t>(k)],
                                  f.corners[static_cast<std::size_t>((k + 1) % 4)], &ck);
          if (tk < t) {
            t = tk;
            c = ck;
          }
        }
      }
      if (t < range_m) {
        range_m = t;
        reflectivity = f.reflectivity;
        cos_incidence = c;
      }
    }
    // Both draws happen for every ray so that one setting does not shift the
    // random stream of the other.
    const double n01 = noise(rng);
    const bool dropped = uniform(rng) < o.dropout_probability;
    float& out = scan.ranges_m[static_cast<std::size_t>(i)];
    float& intensity = scan.intensities[static_cast<std::size_t>(i)];
    if (range_m > o.range_max_m || dropped) {
      out = std::numeric_limits<float>::infinity();
      intensity = 0.0f;
    } else if (range_m < o.range_min_m) {
      out = -std::numeric_limits<float>::infinity();
      intensity = 0.0f;
    } else {
      const double measured_m = range_m + o.range_noise_sigma_m * n01;
      out = static_cast<float>(std::clamp(measured_m, o.range_min_m, o.range_max_m));
      intensity = static_cast<float>(std::clamp(reflectivity * cos_incidence, 0.0, 1.0));
    }
  }
  return scan;
}

std::vector<LaserScan> SimulateScans(const PlanarLidar& lidar, const core::Trajectory& T_map_base) {
  std::vector<LaserScan> scans;
  if (T_map_base.empty()) return scans;
  const double t0 = T_map_base.front().stamp_s;
  const double t1 = T_map_base.back().stamp_s;
  for (std::uint64_t k = 0;; ++k) {
    const double t = t0 + static_cast<double>(k) / lidar.options().rate_hz;
    if (t > t1) break;
    scans.push_back(lidar.ScanAlong(T_map_base, t, k));
  }
  return scans;
}

}  // namespace groundline::sim
