// AddIntrinsicsToBev (floor_calibration.h): the BEV error budget of a
// commissioning report, the mount's and the intrinsics' parts.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/floor_projection.h"

namespace groundline::calibration {
namespace {

using CovarianceMap = IntrinsicsReportSummary::CovarianceMap;

// Var(q) of the map cell holding pixel q; NaN when the cell has none.
Eigen::Matrix2d CellCovariance(const CovarianceMap& map, const Eigen::Vector2d& q, int w, int h) {
  const int ix = std::clamp(static_cast<int>((q.x() + 0.5) / w * map.cells_x), 0, map.cells_x - 1);
  const int iy = std::clamp(static_cast<int>((q.y() + 0.5) / h * map.cells_y), 0, map.cells_y - 1);
  const std::size_t k = static_cast<std::size_t>(iy) * map.cells_x + ix;
  if (k >= map.covariance_px2.size()) return Eigen::Matrix2d::Constant(std::nan(""));
  return map.covariance_px2[k];
}

// Var(q) at pixel q and range r: linear in range between the two maps that
// bracket r, the nearest map outside them.
Eigen::Matrix2d CovarianceAt(const std::vector<CovarianceMap>& maps, const Eigen::Vector2d& q,
                             double range_m, int w, int h) {
  if (maps.empty()) return Eigen::Matrix2d::Constant(std::nan(""));
  if (range_m <= maps.front().range_m) return CellCovariance(maps.front(), q, w, h);
  for (std::size_t i = 0; i + 1 < maps.size(); ++i) {
    if (range_m <= maps[i + 1].range_m) {
      const double a = (range_m - maps[i].range_m) / (maps[i + 1].range_m - maps[i].range_m);
      return (1.0 - a) * CellCovariance(maps[i], q, w, h) +
             a * CellCovariance(maps[i + 1], q, w, h);
    }
  }
  return CellCovariance(maps.back(), q, w, h);
}

}  // namespace

void AddIntrinsicsToBev(const CameraModel& camera, const IntrinsicsReportSummary& intrinsics,
                        FloorCalibration* c) {
  c->bev_budget.clear();
  const FloorProjection floor(camera, c->solution.mount);
  for (const BevError& e : c->bev) {
    BevErrorBudget b;
    b.distance_m = e.distance_m;
    b.extrinsics_rms_mm = e.rms_mm;
    b.total_rms_mm = e.rms_mm;
    b.total_sigma3_mm = e.sigma3_mm;
    const Eigen::Vector2d point(e.distance_m, 0.0);
    const core::Result<Eigen::Vector2d> q = floor.PixelOfFloorPoint(point);
    Eigen::Matrix2d J_floor_pixel;
    if (q.ok() && camera.InImage(*q) && floor.FloorPointOfPixel(*q, &J_floor_pixel).ok()) {
      b.pixel = *q;
      b.range_m =
          (floor.T_base_cam().inverse() * Eigen::Vector3d(point.x(), point.y(), 0.0)).norm();
      const Eigen::Matrix2d var_q = CovarianceAt(intrinsics.covariance_maps, *q, b.range_m,
                                                 camera.width_px(), camera.height_px());
      if (var_q.allFinite() && std::isfinite(e.rms_mm)) {
        const Eigen::Matrix2d intr = J_floor_pixel * var_q * J_floor_pixel.transpose();
        const Eigen::Matrix2d total = intr + e.cov_floor_m2;
        b.intrinsics_rms_mm = 1000.0 * std::sqrt(std::max(0.0, intr.trace()));
        b.total_rms_mm = 1000.0 * std::sqrt(std::max(0.0, total.trace()));
        const double lmax =
            Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(total).eigenvalues().maxCoeff();
        b.total_sigma3_mm = 3000.0 * std::sqrt(std::max(0.0, lmax));
        b.known = true;
      }
    }
    c->bev_budget.push_back(b);
  }
}

}  // namespace groundline::calibration
