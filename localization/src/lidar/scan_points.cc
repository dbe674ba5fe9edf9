#include "groundline/localization/lidar/scan_points.h"

#include <Eigen/Eigenvalues>
#include <cassert>
#include <cmath>
#include <optional>
#include <unordered_set>

namespace groundline::localization::lidar {

core::Status ScanPointsOptions::Validate() const {
  if (!(min_range_m >= 0.0 && max_range_m > min_range_m)) {
    return core::Status::Error("need 0 <= min_range_m < max_range_m");
  }
  if (!(missing_ray_length_m >= 0.0)) return core::Status::Error("missing_ray_length_m < 0");
  if (!(voxel_size_m >= 0.0)) return core::Status::Error("voxel_size_m < 0");
  if (neighbour_beams < 1) return core::Status::Error("neighbour_beams must be >= 1");
  if (!(normal_radius_m > 0.0 && max_planarity > 0.0)) {
    return core::Status::Error("normal_radius_m and max_planarity must be > 0");
  }
  return core::Status::Ok();
}

namespace {

// The unit normal of the line through the neighbours of point i, if planar.
core::Vector2 NormalAt(const std::vector<std::optional<core::Vector2>>& beams, std::size_t i,
                       const core::Vector2& origin, const ScanPointsOptions& options) {
  const core::Vector2& p = *beams[i];
  core::Vector2 mean = core::Vector2::Zero();
  std::vector<core::Vector2> near;
  const int n = static_cast<int>(beams.size());
  for (int k = static_cast<int>(i) - options.neighbour_beams;
       k <= static_cast<int>(i) + options.neighbour_beams; ++k) {
    if (k < 0 || k >= n || !beams[k]) continue;
    if ((*beams[k] - p).norm() > options.normal_radius_m) continue;
    near.push_back(*beams[k]);
    mean += *beams[k];
  }
  if (near.size() < 3) return core::Vector2::Zero();
  mean /= static_cast<double>(near.size());
  core::Matrix2 scatter = core::Matrix2::Zero();
  for (const core::Vector2& q : near) scatter += (q - mean) * (q - mean).transpose();
  Eigen::SelfAdjointEigenSolver<core::Matrix2> eig(scatter);
  if (!(eig.eigenvalues()(1) > 0.0) ||
      eig.eigenvalues()(0) > options.max_planarity * eig.eigenvalues()(1)) {
    return core::Vector2::Zero();
  }
  core::Vector2 normal = eig.eigenvectors().col(0).normalized();
  if (normal.dot(origin - p) < 0.0) normal = -normal;
  return normal;
}

}  // namespace

ScanPoints ScanPointsFromRanges(const std::vector<double>& ranges_m, double angle_min_rad,
                                double angle_increment_rad, double sensor_max_range_m,
                                const core::SE2& T_base_laser, const ScanPointsOptions& options) {
  return ScanPointsFromRanges(ranges_m, angle_min_rad, angle_increment_rad, sensor_max_range_m,
                              T_base_laser, {}, options);
}

ScanPoints ScanPointsFromRanges(const std::vector<double>& ranges_m, double angle_min_rad,
                                double angle_increment_rad, double sensor_max_range_m,
                                const core::SE2& T_base_laser,
                                std::span<const core::SE2> T_base_laser_of_beam,
                                const ScanPointsOptions& options) {
  assert(T_base_laser_of_beam.empty() || T_base_laser_of_beam.size() == ranges_m.size());
  ScanPoints scan;
  scan.sensor_origin_m = T_base_laser.translation();
  std::vector<std::optional<core::Vector2>> beams(ranges_m.size());
  for (std::size_t i = 0; i < ranges_m.size(); ++i) {
    const double r = ranges_m[i];
    const double a = angle_min_rad + static_cast<double>(i) * angle_increment_rad;
    const core::Vector2 dir(std::cos(a), std::sin(a));
    const core::SE2& T_base_beam =
        T_base_laser_of_beam.empty() ? T_base_laser : T_base_laser_of_beam[i];
    if (!std::isfinite(r) || r >= sensor_max_range_m) {
      if (options.missing_ray_length_m > 0.0) {
        scan.misses_m.push_back(T_base_beam * (options.missing_ray_length_m * dir));
      }
      continue;
    }
    if (r < options.min_range_m || r > options.max_range_m) continue;
    beams[i] = T_base_beam * (r * dir);
  }
  std::unordered_set<long long> voxels;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    if (!beams[i]) continue;
    if (options.voxel_size_m > 0.0) {
      const auto vx = static_cast<long long>(std::floor(beams[i]->x() / options.voxel_size_m));
      const auto vy = static_cast<long long>(std::floor(beams[i]->y() / options.voxel_size_m));
      if (!voxels.insert(vx * 1000003LL + vy).second) continue;
    }
    scan.points.push_back({*beams[i], NormalAt(beams, i, scan.sensor_origin_m, options)});
  }
  return scan;
}

}  // namespace groundline::localization::lidar
