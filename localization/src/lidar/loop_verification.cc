#include "groundline/localization/lidar/loop_verification.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace groundline::localization::lidar {
namespace {

// |cos| of the angle between a ray and the normal of the surface it ends
// on, at least this: the margin grows at most fivefold.
constexpr double kMinIncidence = 0.2;

}  // namespace

core::Status FreeSpaceCheckOptions::Validate() const {
  if (!(free_probability > 0.0 && free_probability < 0.5 && occupied_probability > 0.5 &&
        occupied_probability < 1.0)) {
    return core::Status::Error("need 0 < free_probability < 0.5 < occupied_probability < 1");
  }
  if (!(ray_end_margin_m >= 0.0)) return core::Status::Error("ray_end_margin_m must be >= 0");
  if (max_rays < 1) return core::Status::Error("max_rays must be >= 1");
  if (!(max_violation_fraction >= 0.0 && max_violation_fraction <= 1.0)) {
    return core::Status::Error("max_violation_fraction must be in [0, 1]");
  }
  return core::Status::Ok();
}

FreeSpaceCheck CheckFreeSpace(const ProbabilityGrid& grid, const ScanPoints& scan,
                              const core::SE2& T_grid_base, const FreeSpaceCheckOptions& options) {
  FreeSpaceCheck out;
  const std::size_t n = scan.points.size();
  if (n == 0) return out;
  const std::size_t stride =
      std::max<std::size_t>(1, (n + options.max_rays - 1) / options.max_rays);
  const core::Vector2 origin_m = T_grid_base * scan.sensor_origin_m;
  const CellIndex origin = grid.CellOf(origin_m);
  const core::Matrix2 R_base_grid = T_grid_base.Rotation().transpose();
  for (std::size_t i = 0; i < n; i += stride) {
    const ScanPoint& p = scan.points[i];
    const core::Vector2 end_m = T_grid_base * p.point_m;
    ++out.rays;
    const bool in_free = grid.IsFreeAround(grid.CellOf(end_m), options.free_probability);
    bool through_occupied = false;
    const core::Vector2 ray_m = end_m - origin_m;
    const double length_m = ray_m.norm();
    // Traced until ray_end_margin_m from the surface the return lies on;
    // without a normal the surface's angle is unknown: not traced.
    const double incidence = p.has_normal() && length_m > 0.0
                                 ? std::abs(p.normal.dot(R_base_grid * ray_m)) / length_m
                                 : 0.0;
    const double traced_m =
        incidence > 0.0 ? length_m - options.ray_end_margin_m / std::max(incidence, kMinIncidence)
                        : 0.0;
    if (traced_m > 0.0) {
      const CellIndex stop = grid.CellOf(origin_m + ray_m * (traced_m / length_m));
      ForEachCellOnLine(origin, stop, [&](const CellIndex& c) {
        through_occupied = grid.Probability(c) >= options.occupied_probability;
        return !through_occupied;
      });
    }
    out.returns_in_free += in_free;
    out.rays_through_occupied += through_occupied;
    out.violations += in_free || through_occupied;
  }
  out.violation_fraction = static_cast<double>(out.violations) / out.rays;
  out.consistent = out.violation_fraction <= options.max_violation_fraction;
  return out;
}

}  // namespace groundline::localization::lidar
