// The calibration's uncertainty on the floor (bev_uncertainty.h) and the BEV
// error budget of a commissioning report (floor_calibration.h,
// AddIntrinsicsToBev), both from BevBudgetAt.
#include "groundline/calibration/bev_uncertainty.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "groundline/calibration/calibration_report.h"
#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/floor_projection.h"
#include "groundline/core/json_fields.h"

namespace groundline::calibration {
namespace {

using CovarianceMap = IntrinsicsReportSummary::CovarianceMap;
using nlohmann::json;

constexpr long kMaxMapCells = 100000;
constexpr double kMaxCellVarianceM2 = 1.0;

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
Eigen::Matrix2d PixelCovarianceAt(const std::vector<CovarianceMap>& maps, const Eigen::Vector2d& q,
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

double RmsMm(const Eigen::Matrix2d& c) { return 1000.0 * std::sqrt(std::max(0.0, c.trace())); }

double Sigma3Mm(const Eigen::Matrix2d& c) {
  const double lmax = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(c).eigenvalues().maxCoeff();
  return 3000.0 * std::sqrt(std::max(0.0, lmax));
}

}  // namespace

core::Status BevUncertaintyGridOptions::Validate() const {
  const auto bad = [](const std::string& what) {
    return core::Status::Error("BEV uncertainty grid: " + what);
  };
  if (!std::isfinite(x_min_m) || !std::isfinite(x_max_m) || !(x_min_m < x_max_m)) {
    return bad("expected finite x_min_m < x_max_m, got " + std::to_string(x_min_m) + " and " +
               std::to_string(x_max_m));
  }
  if (!std::isfinite(half_width_m) || !(half_width_m > 0.0)) {
    return bad("half_width_m: expected > 0, got " + std::to_string(half_width_m));
  }
  if (!(cell_m >= 0.01 && cell_m <= 1.0)) {
    return bad("cell_m: expected 0.01..1 m, got " + std::to_string(cell_m));
  }
  const double cells = std::ceil((x_max_m - x_min_m) / cell_m) * std::ceil(2 * half_width_m / cell_m);
  if (cells > kMaxMapCells) {
    return bad("expected at most " + std::to_string(kMaxMapCells) + " cells, got " +
               std::to_string(static_cast<long long>(cells)) + " (a larger cell_m or a smaller area)");
  }
  return core::Status::Ok();
}

core::Result<BevPointBudget> BevBudgetAt(const CameraModel& camera,
                                         const FloorExtrinsicsResult& solution,
                                         const IntrinsicsReportSummary* intrinsics,
                                         const Eigen::Vector2d& floor_point_m) {
  const FloorProjection floor(camera, solution.mount);
  const core::Result<Eigen::Vector2d> q = floor.PixelOfFloorPoint(floor_point_m);
  Eigen::Matrix2d J_floor_pixel;
  if (!q.ok() || !camera.InImage(*q) || !floor.FloorPointOfPixel(*q, &J_floor_pixel).ok()) {
    return core::Status::Error("the floor point (" + std::to_string(floor_point_m.x()) + ", " +
                               std::to_string(floor_point_m.y()) + ") m is not in the image");
  }
  core::Result<BevError> mount = BevErrorAt(solution.mount, solution.covariance, floor_point_m);
  if (!mount.ok()) return mount.status();
  BevPointBudget b;
  b.pixel = *q;
  b.range_m = (floor.T_base_cam().inverse() *
               Eigen::Vector3d(floor_point_m.x(), floor_point_m.y(), 0.0))
                  .norm();
  b.mount_m2 = mount->cov_floor_m2;
  if (intrinsics != nullptr) {
    const Eigen::Matrix2d var_q = PixelCovarianceAt(intrinsics->covariance_maps, *q, b.range_m,
                                                    camera.width_px(), camera.height_px());
    if (var_q.allFinite()) {
      b.intrinsics_m2 = J_floor_pixel * var_q * J_floor_pixel.transpose();
      b.intrinsics_known = true;
    }
  }
  return b;
}

void AddIntrinsicsToBev(const CameraModel& camera, const IntrinsicsReportSummary& intrinsics,
                        FloorCalibration* c) {
  c->bev_budget.clear();
  for (const BevError& e : c->bev) {
    BevErrorBudget b;
    b.distance_m = e.distance_m;
    b.extrinsics_rms_mm = e.rms_mm;
    b.total_rms_mm = e.rms_mm;
    b.total_sigma3_mm = e.sigma3_mm;
    const core::Result<BevPointBudget> at =
        BevBudgetAt(camera, c->solution, &intrinsics, Eigen::Vector2d(e.distance_m, 0.0));
    if (at.ok() && at->intrinsics_known && std::isfinite(e.rms_mm)) {
      b.pixel = at->pixel;
      b.range_m = at->range_m;
      b.intrinsics_rms_mm = RmsMm(at->intrinsics_m2);
      b.total_rms_mm = RmsMm(at->Total());
      b.total_sigma3_mm = Sigma3Mm(at->Total());
      b.known = true;
    }
    c->bev_budget.push_back(b);
  }
  core::Result<BevUncertaintyMap> map =
      ComputeBevUncertaintyMap(camera, c->solution, &intrinsics, c->bev_map_grid);
  if (map.ok()) c->bev_map = std::move(map).value();
}

std::optional<Eigen::Matrix2d> BevUncertaintyMap::CovarianceAt(const Eigen::Vector2d& p) const {
  if (cells_x <= 0 || cells_y <= 0 || !(cell_m > 0.0) || !p.allFinite()) return std::nullopt;
  const double fx = std::floor((p.x() - x0_m) / cell_m);
  const double fy = std::floor((p.y() - y0_m) / cell_m);
  if (fx < 0 || fy < 0 || fx >= cells_x || fy >= cells_y) return std::nullopt;
  const Eigen::Matrix2d& c =
      covariance_m2[static_cast<std::size_t>(fy) * cells_x + static_cast<std::size_t>(fx)];
  if (!c.allFinite()) return std::nullopt;
  return c;
}

Eigen::Vector2d BevUncertaintyMap::CellCentre(int ix, int iy) const {
  return {x0_m + (ix + 0.5) * cell_m, y0_m + (iy + 0.5) * cell_m};
}

int BevUncertaintyMap::KnownCells() const {
  return static_cast<int>(std::count_if(covariance_m2.begin(), covariance_m2.end(),
                                        [](const Eigen::Matrix2d& c) { return c.allFinite(); }));
}

double BevUncertaintyMap::WorstRmsMm() const {
  double worst = 0.0;
  for (const Eigen::Matrix2d& c : covariance_m2) {
    if (c.allFinite()) worst = std::max(worst, RmsMm(c));
  }
  return worst;
}

core::Result<BevUncertaintyMap> ComputeBevUncertaintyMap(const CameraModel& camera,
                                                         const FloorExtrinsicsResult& solution,
                                                         const IntrinsicsReportSummary* intrinsics,
                                                         const BevUncertaintyGridOptions& grid) {
  if (core::Status s = grid.Validate(); !s.ok()) return s;
  if (core::Status s = solution.mount.Validate(); !s.ok()) return s;
  BevUncertaintyMap map;
  map.cell_m = grid.cell_m;
  map.x0_m = grid.x_min_m;
  map.y0_m = -grid.half_width_m;
  map.cells_x = static_cast<int>(std::ceil((grid.x_max_m - grid.x_min_m) / grid.cell_m - 1e-9));
  map.cells_y = static_cast<int>(std::ceil(2.0 * grid.half_width_m / grid.cell_m - 1e-9));
  map.includes_intrinsics = intrinsics != nullptr;
  map.camera_fingerprint = CameraFingerprint(camera);
  map.covariance_m2.assign(static_cast<std::size_t>(map.cells_x) * map.cells_y,
                           Eigen::Matrix2d::Constant(std::nan("")));
  for (int iy = 0; iy < map.cells_y; ++iy) {
    for (int ix = 0; ix < map.cells_x; ++ix) {
      const core::Result<BevPointBudget> b =
          BevBudgetAt(camera, solution, intrinsics, map.CellCentre(ix, iy));
      if (!b.ok() || (intrinsics != nullptr && !b->intrinsics_known)) continue;
      const Eigen::Matrix2d total = b->Total();
      // A cell near the horizon can carry a covariance too large to mean anything.
      if (!total.allFinite() || total.maxCoeff() > kMaxCellVarianceM2) continue;
      map.covariance_m2[static_cast<std::size_t>(iy) * map.cells_x + ix] = total;
    }
  }
  if (map.KnownCells() == 0) {
    return core::Status::Error(
        "BEV uncertainty map: the camera sees no cell of the grid (x " +
        std::to_string(grid.x_min_m) + ".." + std::to_string(grid.x_max_m) + " m, y +-" +
        std::to_string(grid.half_width_m) + " m)");
  }
  return map;
}

std::string BevUncertaintyJson(const BevUncertaintyMap& map) {
  json cells = json::array();
  for (const Eigen::Matrix2d& c : map.covariance_m2) {
    if (c.allFinite()) {
      cells.push_back({c(0, 0), c(0, 1), c(1, 1)});
    } else {
      cells.push_back(nullptr);
    }
  }
  const json j = {{"format", "groundline.bev_uncertainty"},
                  {"version", 1},
                  {"frame", "base_link"},
                  {"camera_fingerprint", map.camera_fingerprint},
                  {"includes_intrinsics", map.includes_intrinsics},
                  {"x0_m", map.x0_m},
                  {"y0_m", map.y0_m},
                  {"cell_m", map.cell_m},
                  {"cells_x", map.cells_x},
                  {"cells_y", map.cells_y},
                  {"worst_rms_mm", map.WorstRmsMm()},
                  {"covariance_m2", cells}};
  return j.dump(1) + "\n";
}

core::Result<BevUncertaintyMap> ReadBevUncertaintyMap(const std::filesystem::path& path) {
  json j;
  if (core::Status s = core::ReadJsonFile(path, "BEV uncertainty map (bev_uncertainty.json)", &j);
      !s.ok()) {
    return s;
  }
  const std::string where = path.string();
  core::JsonFieldReader r(where);
  if (!j.is_object()) {
    r.Fail("(document)", "an object", j.dump());
    return r.status();
  }
  if (r.String(j, "", "format") != "groundline.bev_uncertainty" && r.ok()) {
    r.Fail("format", "\"groundline.bev_uncertainty\"", j.at("format").dump());
  }
  const json* version = r.Get(j, "", "version");
  if (version != nullptr && core::JsonInteger(*version, 1, 1) != 1) {
    r.Fail("version", "1 (the version this groundline reads)", version->dump());
  }
  if (r.ok() && r.String(j, "", "frame") != "base_link" && r.ok()) {
    r.Fail("frame", "\"base_link\"", j.at("frame").dump());
  }
  BevUncertaintyMap map;
  map.camera_fingerprint = r.String(j, "", "camera_fingerprint");
  if (const json* b = r.Get(j, "", "includes_intrinsics"); b != nullptr) {
    if (b->is_boolean()) {
      map.includes_intrinsics = b->get<bool>();
    } else {
      r.Fail("includes_intrinsics", "true or false", b->dump());
    }
  }
  map.x0_m = r.Finite(j, "", "x0_m");
  map.y0_m = r.Finite(j, "", "y0_m");
  map.cell_m = r.Finite(j, "", "cell_m");
  if (r.ok() && !(map.cell_m >= 0.01 && map.cell_m <= 1.0)) {
    r.Fail("cell_m", "0.01..1 m", j.at("cell_m").dump());
  }
  if (r.ok() && (std::abs(map.x0_m) > 1000.0 || std::abs(map.y0_m) > 1000.0)) {
    r.Fail("x0_m, y0_m", "within +-1000 m of base_link",
           j.at("x0_m").dump() + ", " + j.at("y0_m").dump());
  }
  for (const char* key : {"cells_x", "cells_y"}) {
    const json* n = r.Get(j, "", key);
    if (n == nullptr) continue;
    const std::optional<std::int64_t> v = core::JsonInteger(*n, 1, kMaxMapCells);
    if (!v) {
      r.Fail(key, "an integer 1.." + std::to_string(kMaxMapCells), n->dump());
      continue;
    }
    (key[6] == 'x' ? map.cells_x : map.cells_y) = static_cast<int>(*v);
  }
  if (!r.ok()) return r.status();
  const long cells = static_cast<long>(map.cells_x) * map.cells_y;
  if (cells > kMaxMapCells) {
    r.Fail("cells_x, cells_y", "at most " + std::to_string(kMaxMapCells) + " cells in all",
           std::to_string(map.cells_x) + " x " + std::to_string(map.cells_y));
    return r.status();
  }
  const json* list = r.Get(j, "", "covariance_m2");
  if (list == nullptr) return r.status();
  if (!list->is_array() || static_cast<long>(list->size()) != cells) {
    r.Fail("covariance_m2",
           "an array of cells_x * cells_y = " + std::to_string(cells) + " cells",
           list->is_array() ? std::to_string(list->size()) + " cells" : list->dump());
    return r.status();
  }
  map.covariance_m2.reserve(static_cast<std::size_t>(cells));
  for (std::size_t i = 0; i < list->size(); ++i) {
    const json& c = (*list)[i];
    if (c.is_null()) {
      map.covariance_m2.push_back(Eigen::Matrix2d::Constant(std::nan("")));
      continue;
    }
    const std::string field = "covariance_m2[" + std::to_string(i) + "]";
    const bool numbers = c.is_array() && c.size() == 3 &&
                         std::all_of(c.begin(), c.end(), [](const json& v) { return v.is_number(); });
    if (!numbers) {
      r.Fail(field, "null or [xx, xy, yy] (m^2)", c.dump());
      return r.status();
    }
    const double xx = c[0].get<double>(), xy = c[1].get<double>(), yy = c[2].get<double>();
    // Positive semi-definite: a mount known exactly but for its pitch moves
    // every floor point along one direction only (a rank-1 covariance).
    if (!(std::isfinite(xx) && std::isfinite(xy) && std::isfinite(yy) && xx >= 0.0 &&
          yy >= 0.0 && xx + yy > 0.0 && xx * yy - xy * xy >= -1e-9 * xx * yy &&
          xx <= kMaxCellVarianceM2 && yy <= kMaxCellVarianceM2)) {
      r.Fail(field,
             "a positive semi-definite, non-zero covariance [xx, xy, yy] with variances at most "
             "1 m^2",
             c.dump());
      return r.status();
    }
    Eigen::Matrix2d m;
    m << xx, xy, xy, yy;
    map.covariance_m2.push_back(m);
  }
  if (map.KnownCells() == 0) {
    r.Fail("covariance_m2", "at least one known cell", "only null");
    return r.status();
  }
  return map;
}

core::Status CheckBevUncertaintyCamera(const BevUncertaintyMap& map, const CameraModel& camera,
                                       const std::string& map_source) {
  const std::string fingerprint = CameraFingerprint(camera);
  if (map.camera_fingerprint == fingerprint) return core::Status::Ok();
  return core::Status::Error(
      map_source + ": the BEV uncertainty map is for another camera model (camera_fingerprint " +
      map.camera_fingerprint + ", the camera in use has " + fingerprint +
      "); use the bev_uncertainty.json that `groundline calibrate floor` wrote with this camera's "
      "intrinsics, or recommission");
}

}  // namespace groundline::calibration
