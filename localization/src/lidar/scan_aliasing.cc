#include "groundline/localization/lidar/scan_aliasing.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace groundline::localization::lidar {
namespace {

std::int64_t Key(std::int64_t x, std::int64_t y) { return (x << 32) ^ (y & 0xffffffff); }

}  // namespace

core::Status ScanAliasingOptions::Validate() const {
  if (!(resolution_m > 0.0 && min_shift_m > 0.0 && max_shift_m >= min_shift_m &&
        min_score_ratio > 0.0 && min_score_ratio <= 1.0 && min_points >= 1)) {
    return core::Status::Error(
        "ScanAliasingOptions: need resolution_m > 0, 0 < min_shift_m <= max_shift_m, "
        "min_score_ratio in (0, 1], min_points >= 1");
  }
  return core::Status::Ok();
}

ScanAliasing DetectScanAliasing(const std::vector<ScanPoint>& points,
                                const core::Vector2& direction,
                                const ScanAliasingOptions& options) {
  ScanAliasing out;
  out.direction = direction.normalized();
  if (static_cast<int>(points.size()) < options.min_points) return out;
  const double inv = 1.0 / options.resolution_m;
  std::unordered_set<std::int64_t> marked;
  marked.reserve(points.size() * 9);
  for (const ScanPoint& p : points) {
    const std::int64_t cx = std::llround(p.point_m.x() * inv);
    const std::int64_t cy = std::llround(p.point_m.y() * inv);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) marked.insert(Key(cx + dx, cy + dy));
    }
  }
  const int steps = static_cast<int>(std::floor(options.max_shift_m * inv + 1e-9));
  const int first = static_cast<int>(std::ceil(options.min_shift_m * inv - 1e-9));
  for (int k = first; k <= steps; ++k) {
    for (double sign : {-1.0, 1.0}) {
      const core::Vector2 shift = sign * k * options.resolution_m * out.direction;
      int hits = 0;
      for (const ScanPoint& p : points) {
        const core::Vector2 q = (p.point_m + shift) * inv;
        hits += marked.count(Key(std::llround(q.x()), std::llround(q.y())));
      }
      const double score = static_cast<double>(hits) / static_cast<double>(points.size());
      if (score > out.best_score) {
        out.best_score = score;
        out.best_shift_m = sign * k * options.resolution_m;
      }
    }
  }
  out.aliased = out.best_score >= options.min_score_ratio;
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
