// The calibration's uncertainty carried into the bird's-eye view, per cell of
// a floor grid: the covariance (m^2, base_link x and y) of the floor point
// that IPM assigns to the pixel seeing a cell's centre, from
//   - the mount's covariance (floor_extrinsics.h, BevErrorAt): the pixel is
//     back-projected through a perturbed mount, and
//   - the intrinsics' projection uncertainty (the intrinsics report's Var(q)
//     maps, projection_uncertainty.h) through the floor projection's Jacobian,
//     Sigma_intrinsics = J_floor_pixel Var(q) J_floor_pixel',
// the two independent (they come from different data), so they add.
//
// `calibrate floor` writes it as bev_uncertainty.json next to extrinsics.yaml
// and shows it in the commissioning report; perception takes it as the floor
// of its line covariances (perception/line_extractor.h, calibration_floor):
// no line can be known better than the calibration that put it on the floor.
//
// The covariance is per point. A calibration error moves neighbouring points
// together (it is a bias of the whole view, constant over the frames), so the
// map states the marginal of each cell, not their correlation.
#ifndef GROUNDLINE_CALIBRATION_BEV_UNCERTAINTY_H_
#define GROUNDLINE_CALIBRATION_BEV_UNCERTAINTY_H_

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/floor_extrinsics.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct IntrinsicsReportSummary;  // floor_calibration.h

// The floor grid of the map, base_link: x_min_m..x_max_m ahead,
// -half_width_m..half_width_m to the side, square cells of cell_m. The
// default covers every BEV the perception presets use (0.6-2.4 m ahead of
// the reference mount, the camera's footprint) with room for other mounts.
struct BevUncertaintyGridOptions {
  double x_min_m = 0.0;
  double x_max_m = 4.0;
  double half_width_m = 2.0;
  double cell_m = 0.2;

  // x_min_m < x_max_m, half_width_m > 0, cell_m in [0.01, 1] m, at most
  // 100,000 cells; the message names the field.
  core::Status Validate() const;
};

// The floor error at one floor point.
struct BevPointBudget {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // where the point is seen
  double range_m = 0.0;                             // camera to the point
  Eigen::Matrix2d mount_m2 = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d intrinsics_m2 = Eigen::Matrix2d::Zero();  // zero without intrinsics
  bool intrinsics_known = false;  // an intrinsics report with Var(q) at that pixel
  Eigen::Matrix2d Total() const { return mount_m2 + intrinsics_m2; }
};

// The budget at a floor point (base_link) seen through `solution`'s mount
// and covariance; intrinsics (nullable) adds its projection uncertainty at
// the point's pixel and range (linear in range between the report's maps,
// the nearest map outside them). Fails when the point is not in the image.
core::Result<BevPointBudget> BevBudgetAt(const CameraModel& camera,
                                         const FloorExtrinsicsResult& solution,
                                         const IntrinsicsReportSummary* intrinsics,
                                         const Eigen::Vector2d& floor_point_m);

struct BevUncertaintyMap {
  double x0_m = 0.0;  // corner of cell (0, 0): the grid's minimum x and y
  double y0_m = 0.0;
  double cell_m = 0.0;
  int cells_x = 0;  // along base x (ahead)
  int cells_y = 0;  // along base y (left)
  // Whether the intrinsics' part is in (an intrinsics report was given); the
  // mount's part is always in.
  bool includes_intrinsics = false;
  std::string camera_fingerprint;  // CameraFingerprint of the camera it holds for
  // Row-major over y then x: cell (ix, iy) is covariance_m2[iy * cells_x + ix];
  // NaN where the cell's centre is not seen by the camera.
  std::vector<Eigen::Matrix2d> covariance_m2;

  // The covariance of the cell holding the floor point; nullopt outside the
  // grid or where the cell is not seen.
  std::optional<Eigen::Matrix2d> CovarianceAt(const Eigen::Vector2d& floor_point_m) const;
  Eigen::Vector2d CellCentre(int ix, int iy) const;
  int KnownCells() const;
  // The largest sqrt(trace) over the known cells, mm (0 when none is known).
  double WorstRmsMm() const;
};

// The map over `grid` for the camera and the solved mount, with the
// intrinsics' part when `intrinsics` is given. Errors: invalid grid options,
// a camera that sees no cell.
core::Result<BevUncertaintyMap> ComputeBevUncertaintyMap(
    const CameraModel& camera, const FloorExtrinsicsResult& solution,
    const IntrinsicsReportSummary* intrinsics, const BevUncertaintyGridOptions& grid = {});

// bev_uncertainty.json (docs/calibration.md, "The BEV uncertainty map"):
// {"format": "groundline.bev_uncertainty", "version": 1, "frame": "base_link",
//  "camera_fingerprint", "includes_intrinsics", "x0_m", "y0_m", "cell_m",
//  "cells_x", "cells_y", "covariance_m2": [[xx, xy, yy] | null, ...]}.
std::string BevUncertaintyJson(const BevUncertaintyMap& map);

// Reads a bev_uncertainty.json. Errors name the file, the field and what was
// expected; every known covariance must be symmetric positive semi-definite
// and not zero (xx, yy >= 0, xx yy >= xy^2 to 1e-9 relative; a mount
// uncertain in one number only gives rank 1), with variances at most 1 m^2;
// the grid at most 100,000 cells.
core::Result<BevUncertaintyMap> ReadBevUncertaintyMap(const std::filesystem::path& path);

// Ok when the map was computed for this camera (its CameraFingerprint);
// otherwise the error names the map's source and says to recommission.
core::Status CheckBevUncertaintyCamera(const BevUncertaintyMap& map, const CameraModel& camera,
                                       const std::string& map_source);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_BEV_UNCERTAINTY_H_
