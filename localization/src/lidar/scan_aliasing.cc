#include "groundline/localization/lidar/scan_aliasing.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace groundline::localization::lidar {
namespace {

enum Cell : std::uint8_t { kCellUnknown = 0, kCellFree = 1, kCellOccupied = 2 };

// The scan's local occupancy grid (base frame).
class ScanGrid {
 public:
  ScanGrid(const ScanPoints& scan, const ScanAliasingOptions& options)
      : inv_(1.0 / options.resolution_m) {
    core::Vector2 lo = scan.sensor_origin_m, hi = scan.sensor_origin_m;
    for (const ScanPoint& p : scan.points) {
      lo = lo.cwiseMin(p.point_m);
      hi = hi.cwiseMax(p.point_m);
    }
    for (const core::Vector2& m : scan.misses_m) {
      lo = lo.cwiseMin(m);
      hi = hi.cwiseMax(m);
    }
    x0_ = std::lround(lo.x() * inv_) - 1;
    y0_ = std::lround(lo.y() * inv_) - 1;
    nx_ = std::lround(hi.x() * inv_) - x0_ + 2;
    ny_ = std::lround(hi.y() * inv_) - y0_ + 2;
    cells_.assign(static_cast<std::size_t>(nx_ * ny_), kCellUnknown);
    for (const ScanPoint& p : scan.points) {
      Ray(scan.sensor_origin_m, p.point_m, options.free_stop_m, 0.5 * options.resolution_m);
    }
    for (const core::Vector2& m : scan.misses_m) {
      Ray(scan.sensor_origin_m, m, 0.0, 0.5 * options.resolution_m);
    }
    for (const ScanPoint& p : scan.points) {
      const long cx = std::lround(p.point_m.x() * inv_);
      const long cy = std::lround(p.point_m.y() * inv_);
      for (long dx = -1; dx <= 1; ++dx) {
        for (long dy = -1; dy <= 1; ++dy) Mark(cx + dx, cy + dy, kCellOccupied);
      }
    }
  }

  Cell At(const core::Vector2& p_m) const {
    const long cx = std::lround(p_m.x() * inv_) - x0_;
    const long cy = std::lround(p_m.y() * inv_) - y0_;
    if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) return kCellUnknown;
    return static_cast<Cell>(cells_[static_cast<std::size_t>(cy * nx_ + cx)]);
  }

 private:
  void Mark(long cx, long cy, Cell value) {
    cx -= x0_;
    cy -= y0_;
    if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) return;
    std::uint8_t& cell = cells_[static_cast<std::size_t>(cy * nx_ + cx)];
    cell = std::max<std::uint8_t>(cell, value);
  }

  // Marks free the cells from origin towards end, stopping stop_m short of it.
  void Ray(const core::Vector2& origin, const core::Vector2& end, double stop_m, double step_m) {
    const core::Vector2 delta = end - origin;
    const double length_m = delta.norm() - stop_m;
    if (length_m <= 0.0) return;
    const core::Vector2 unit = delta.normalized();
    for (double t = 0.0; t < length_m; t += step_m) {
      const core::Vector2 q = origin + t * unit;
      Mark(std::lround(q.x() * inv_), std::lround(q.y() * inv_), kCellFree);
    }
  }

  double inv_;
  long x0_ = 0, y0_ = 0, nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> cells_;
};

// The weight of each point along d: (n . d)^2 (0 without a normal), each
// surface's total capped at options.max_surface_points. A surface is a run of
// consecutive points (beam order) less than surface_gap_m apart.
std::vector<double> SurfaceCappedWeights(const std::vector<ScanPoint>& points,
                                         const core::Vector2& d,
                                         const ScanAliasingOptions& options) {
  std::vector<double> weights(points.size(), 0.0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].has_normal()) weights[i] = std::pow(points[i].normal.dot(d), 2);
  }
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= points.size(); ++i) {
    if (i < points.size() &&
        (points[i].point_m - points[i - 1].point_m).norm() <= options.surface_gap_m) {
      continue;
    }
    double total = 0.0;
    for (std::size_t j = begin; j < i; ++j) total += weights[j];
    if (total > options.max_surface_points) {
      const double scale = options.max_surface_points / total;
      for (std::size_t j = begin; j < i; ++j) weights[j] *= scale;
    }
    begin = i;
  }
  return weights;
}

}  // namespace

core::Status ScanAliasingOptions::Validate() const {
  if (!(resolution_m > 0.0 && min_shift_m > 0.0 && max_shift_m >= min_shift_m &&
        free_stop_m >= 0.0 && min_consistent_share > 0.0 && min_consistent_share <= 1.0 &&
        surface_gap_m > 0.0 && max_surface_points > 0.0 && min_points >= 1)) {
    return core::Status::Error(
        "ScanAliasingOptions: need resolution_m > 0, 0 < min_shift_m <= max_shift_m, "
        "free_stop_m >= 0, min_consistent_share in (0, 1], surface_gap_m > 0, "
        "max_surface_points > 0, min_points >= 1");
  }
  return core::Status::Ok();
}

ScanAliasing DetectScanAliasing(const ScanPoints& scan, const MatchInformation& information,
                                const ScanAliasingOptions& options) {
  ScanAliasing out;
  out.direction = WeakestTranslation(information);
  if (static_cast<int>(scan.points.size()) < options.min_points) return out;
  const ScanGrid grid(scan, options);
  const std::vector<double> weights = SurfaceCappedWeights(scan.points, out.direction, options);
  const double inv = 1.0 / options.resolution_m;
  const int first = static_cast<int>(std::ceil(options.min_shift_m * inv - 1e-9));
  const int last = static_cast<int>(std::floor(options.max_shift_m * inv + 1e-9));
  for (int k = first; k <= last; ++k) {
    const core::Vector2 shift = k * options.resolution_m * out.direction;
    double consistent = 0.0, contradicted = 0.0;
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      const double weight = weights[i];
      if (weight <= 0.0) continue;
      const ScanPoint& p = scan.points[i];
      for (const core::Vector2& q :
           {core::Vector2(p.point_m + shift), core::Vector2(p.point_m - shift)}) {
        const Cell cell = grid.At(q);
        if (cell == kCellOccupied) consistent += weight;
        if (cell == kCellFree) contradicted += weight;
      }
    }
    const double evidence = consistent + contradicted;
    const double score = evidence > 0.0 ? consistent / evidence : 1.0;
    if (k == first || score > out.best_score) {
      out.best_score = score;
      out.best_shift_m = k * options.resolution_m;
      out.evidence = 0.5 * evidence;
    }
  }
  out.aliased = out.best_score >= options.min_consistent_share;
  return out;
}

core::Vector2 WeakestTranslation(const MatchInformation& information) {
  Eigen::SelfAdjointEigenSolver<core::Matrix2> eig(information.information.topLeftCorner<2, 2>());
  return eig.eigenvectors().col(0).normalized();
}

core::Matrix3 RemoveTranslation(const core::Matrix3& sqrt_information,
                                const core::Vector2& direction) {
  core::Vector3 u = core::Vector3::Zero();
  u.head<2>() = direction.normalized();
  return sqrt_information * (core::Matrix3::Identity() - u * u.transpose());
}

}  // namespace groundline::localization::lidar
