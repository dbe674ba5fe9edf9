#include "groundline/perception/bev_remap.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace groundline::perception {
namespace {

constexpr int kMaxCellsPerSide = 4096;

}  // namespace

core::Status BevGridOptions::Validate() const {
  for (const auto& [name, value] :
       {std::pair{"x_min_m", x_min_m}, std::pair{"x_max_m", x_max_m}, std::pair{"y_min_m", y_min_m},
        std::pair{"y_max_m", y_max_m}, std::pair{"cell_m", cell_m}}) {
    if (!std::isfinite(value)) {
      return core::Status::Error(std::string("BevGridOptions.") + name + " must be finite");
    }
  }
  if (cell_m <= 0.0) return core::Status::Error("BevGridOptions.cell_m must be > 0");
  if (x_max_m <= x_min_m) return core::Status::Error("BevGridOptions: x_max_m must exceed x_min_m");
  if (y_max_m <= y_min_m) return core::Status::Error("BevGridOptions: y_max_m must exceed y_min_m");
  if ((x_max_m - x_min_m) / cell_m > kMaxCellsPerSide ||
      (y_max_m - y_min_m) / cell_m > kMaxCellsPerSide) {
    return core::Status::Error("BevGridOptions: more than 4096 cells per side; increase cell_m");
  }
  return core::Status::Ok();
}

core::Status BevRemap::Options::Validate() const {
  if (supersampling < 1 || supersampling > 4) {
    return core::Status::Error("BevRemap::Options.supersampling must be in 1..4, got " +
                               std::to_string(supersampling));
  }
  if (supersampling_across < 0 || supersampling_across > 4) {
    return core::Status::Error(
        "BevRemap::Options.supersampling_across must be in 0..4 (0: supersampling), got " +
        std::to_string(supersampling_across));
  }
  return grid.Validate();
}

BevGrid::BevGrid(const BevGridOptions& options) : options_(options) {
  assert(options.Validate().ok());
  rows_ = std::max(
      1, static_cast<int>(std::lround((options.x_max_m - options.x_min_m) / options.cell_m)));
  cols_ = std::max(
      1, static_cast<int>(std::lround((options.y_max_m - options.y_min_m) / options.cell_m)));
}

Eigen::Vector2d BevGrid::FloorPointOfCell(const Eigen::Vector2d& cell) const {
  return {options_.x_max_m - (cell.y() + 0.5) * options_.cell_m,
          options_.y_max_m - (cell.x() + 0.5) * options_.cell_m};
}

Eigen::Vector2d BevGrid::CellOfFloorPoint(const Eigen::Vector2d& floor_point_m) const {
  return {(options_.y_max_m - floor_point_m.y()) / options_.cell_m - 0.5,
          (options_.x_max_m - floor_point_m.x()) / options_.cell_m - 0.5};
}

Eigen::Matrix3d BevGrid::FloorFromCell() const {
  const double c = options_.cell_m;
  Eigen::Matrix3d A;
  A << 0.0, -c, options_.x_max_m - 0.5 * c,  //
      -c, 0.0, options_.y_max_m - 0.5 * c,   //
      0.0, 0.0, 1.0;
  return A;
}

BevRemap::BevRemap(calibration::CameraModel camera, const calibration::CameraMount& mount,
                   const Options& options)
    : camera_(std::move(camera)), options_(options), grid_(options.grid) {
  assert(options.Validate().ok());
  const int n = grid_.rows() * grid_.cols();
  floor_points_base_.resize(3, n);
  for (int row = 0; row < grid_.rows(); ++row) {
    for (int col = 0; col < grid_.cols(); ++col) {
      const Eigen::Vector2d p = grid_.FloorPointOfCell({col, row});
      floor_points_base_.col(row * grid_.cols() + col) << p.x(), p.y(), 0.0;
    }
  }
  pixel_map_.create(grid_.rows(), grid_.cols(), CV_32FC2);
  remap_map_.create(grid_.rows(), grid_.cols(), CV_32FC2);
  valid_mask_.create(grid_.rows(), grid_.cols(), CV_8UC1);
  Rebuild(mount);
}

void BevRemap::Rebuild(const calibration::CameraMount& mount) {
  assert(mount.Validate().ok());
  mount_ = mount;
  const Eigen::Isometry3d T_cam_base = calibration::BaseFromCamera(mount).inverse();
  points_cam_.noalias() = T_cam_base.linear() * floor_points_base_;
  points_cam_.colwise() += T_cam_base.translation();
  camera_.ProjectBatch(points_cam_, &pixels_, &projected_);

  const float u_max = static_cast<float>(camera_.width_px() - 1);
  const float v_max = static_cast<float>(camera_.height_px() - 1);
  valid_cells_ = 0;
  for (int row = 0; row < grid_.rows(); ++row) {
    auto* map_row = pixel_map_.ptr<cv::Vec2f>(row);
    auto* safe_row = remap_map_.ptr<cv::Vec2f>(row);
    auto* mask_row = valid_mask_.ptr<std::uint8_t>(row);
    for (int col = 0; col < grid_.cols(); ++col) {
      const int i = row * grid_.cols() + col;
      const float u = static_cast<float>(pixels_(0, i));
      const float v = static_cast<float>(pixels_(1, i));
      const bool valid = projected_[i] != 0 && u >= 0.0f && u <= u_max && v >= 0.0f && v <= v_max;
      map_row[col] = valid ? cv::Vec2f(u, v) : cv::Vec2f(-1.0f, -1.0f);
      safe_row[col] = valid ? cv::Vec2f(u, v) : cv::Vec2f(0.0f, 0.0f);
      mask_row[col] = valid ? 255 : 0;
      valid_cells_ += valid ? 1 : 0;
    }
  }
  cv::compare(valid_mask_, 0, invalid_mask_, cv::CMP_EQ);
  if (options_.fill_unseen) FillUnseenFromNearestSeen();
  if (options_.fixed_point) {
    cv::convertMaps(remap_map_, cv::noArray(), fixed_map_xy_, fixed_map_frac_, CV_16SC2);
  }
  if (Supersampled()) {
    // INTER_LINEAR resize samples the source at (dst + 0.5) / s - 0.5: the sub-cell centres.
    cv::Mat fine;
    cv::resize(remap_map_, fine, cv::Size(), options_.SamplesAcross(), options_.supersampling,
               cv::INTER_LINEAR);
    cv::convertMaps(fine, cv::noArray(), fine_map_xy_, fine_map_frac_, CV_16SC2);
  }
}

void BevRemap::FillUnseenFromNearestSeen() {
  if (valid_cells_ == 0 || valid_cells_ == grid_.rows() * grid_.cols()) return;
  // DIST_LABEL_PIXEL: every seen (zero) cell of invalid_mask_ gets its own
  // label, and every unseen cell the label of the seen cell nearest to it.
  cv::Mat distance, labels;
  cv::distanceTransform(invalid_mask_, distance, labels, cv::DIST_L2, cv::DIST_MASK_5,
                        cv::DIST_LABEL_PIXEL);
  double max_label = 0.0;
  cv::minMaxLoc(labels, nullptr, &max_label);
  std::vector<cv::Vec2f> pixel_of_label(static_cast<size_t>(max_label) + 1);
  for (int row = 0; row < grid_.rows(); ++row) {
    const auto* mask_row = valid_mask_.ptr<std::uint8_t>(row);
    const auto* label_row = labels.ptr<int>(row);
    const auto* map_row = remap_map_.ptr<cv::Vec2f>(row);
    for (int col = 0; col < grid_.cols(); ++col) {
      if (mask_row[col] != 0) pixel_of_label[label_row[col]] = map_row[col];
    }
  }
  for (int row = 0; row < grid_.rows(); ++row) {
    const auto* mask_row = valid_mask_.ptr<std::uint8_t>(row);
    const auto* label_row = labels.ptr<int>(row);
    auto* map_row = remap_map_.ptr<cv::Vec2f>(row);
    for (int col = 0; col < grid_.cols(); ++col) {
      if (mask_row[col] == 0) map_row[col] = pixel_of_label[label_row[col]];
    }
  }
}

void BevRemap::Apply(const cv::Mat& image, cv::Mat* bev) const {
  assert(bev != nullptr);
  assert(image.cols == camera_.width_px() && image.rows == camera_.height_px());
  // Invalid cells read pixel (0, 0) and are zeroed afterwards: cv::remap takes
  // a per-pixel slow path for map entries outside the image (5x slower here).
  if (Supersampled()) {
    cv::Mat fine;
    cv::remap(image, fine, fine_map_xy_, fine_map_frac_, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
              cv::Scalar::all(0));
    cv::resize(fine, *bev, cv::Size(grid_.cols(), grid_.rows()), 0.0, 0.0, cv::INTER_AREA);
  } else if (options_.fixed_point) {
    cv::remap(image, *bev, fixed_map_xy_, fixed_map_frac_, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
              cv::Scalar::all(0));
  } else {
    cv::remap(image, *bev, remap_map_, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
              cv::Scalar::all(0));
  }
  if (!options_.fill_unseen) bev->setTo(cv::Scalar::all(0), invalid_mask_);
}

Eigen::Matrix3d PinholeImageFromCell(const BevGrid& grid, const calibration::CameraMount& mount,
                                     const Eigen::Matrix3d& K) {
  const Eigen::Matrix3d H_img_floor =
      calibration::FloorToImageHomography(calibration::BaseFromCamera(mount), K);
  return H_img_floor * grid.FloorFromCell();
}

namespace {

// The floor rectangle spanned by the centres of the probe cells (probe_cell_m
// square cells over [x_min, x_max] x [y_min, y_max]) that the camera sees and
// resolves: one pixel covers at most max_floor_per_px metres of floor (the
// larger axis of its footprint, 1 / the smaller singular value of d pixel /
// d floor, differenced between probe cells). Nothing: nullopt.
std::optional<BevGridOptions> ResolvedCellCentres(const calibration::CameraModel& camera,
                                                  const calibration::CameraMount& mount,
                                                  const BevGridOptions& probe_grid,
                                                  double max_floor_per_px) {
  BevRemap::Options options;
  options.fill_unseen = false;
  options.grid = probe_grid;
  const BevRemap probe(camera, mount, options);
  const cv::Mat& map = probe.pixel_map();
  const double probe_cell_m = probe.grid().cell_m();
  const auto step = [&](int row, int col, int d_row, int d_col, Eigen::Vector2d* d) {
    for (const int sign : {1, -1}) {
      const int r = row + sign * d_row, c = col + sign * d_col;
      if (r < 0 || c < 0 || r >= map.rows || c >= map.cols) continue;
      const cv::Vec2f a = map.at<cv::Vec2f>(row, col), b = map.at<cv::Vec2f>(r, c);
      if (b[0] < 0.0f) continue;
      *d = sign * Eigen::Vector2d(b[0] - a[0], b[1] - a[1]) / probe_cell_m;
      return true;
    }
    return false;
  };
  std::vector<cv::Point> valid;
  for (int row = 0; row < map.rows; ++row) {
    for (int col = 0; col < map.cols; ++col) {
      if (probe.valid_mask().at<std::uint8_t>(row, col) == 0) continue;
      Eigen::Matrix2d J;  // d pixel / d (col, row) in metres of floor
      Eigen::Vector2d d_col, d_row;
      if (!step(row, col, 0, 1, &d_col) || !step(row, col, 1, 0, &d_row)) continue;
      J << d_col, d_row;
      // The smaller singular value of a 2x2 matrix, closed form.
      const double a = J.squaredNorm(), det = std::abs(J.determinant());
      const double s_min =
          std::sqrt(std::max(0.0, 0.5 * (a - std::sqrt(std::max(0.0, a * a - 4.0 * det * det)))));
      if (s_min > 0.0 && 1.0 / s_min <= max_floor_per_px) valid.emplace_back(col, row);
    }
  }
  if (valid.empty()) return std::nullopt;
  const cv::Rect box = cv::boundingRect(valid);
  const BevGrid& g = probe.grid();
  // Row 0 is the far edge (x_max), column 0 the left edge (y_max).
  const Eigen::Vector2d far_left = g.FloorPointOfCell(Eigen::Vector2d(box.x, box.y));
  const Eigen::Vector2d near_right =
      g.FloorPointOfCell(Eigen::Vector2d(box.x + box.width - 1, box.y + box.height - 1));
  BevGridOptions centres;
  centres.cell_m = probe_cell_m;
  centres.x_min_m = near_right.x();
  centres.x_max_m = far_left.x();
  centres.y_min_m = near_right.y();
  centres.y_max_m = far_left.y();
  return centres;
}

// A probe grid of cell_m cells whose far-left corner lies on the lattice of
// cell_m through the origin (so that one camera gets the same cells however
// the probe's region is chosen), covering [x_min, x_max] x [y_min, y_max].
BevGridOptions ProbeGrid(double x_min, double x_max, double y_min, double y_max, double cell_m) {
  const auto on_lattice = [&](double v) { return cell_m * std::ceil(v / cell_m - 1e-9); };
  BevGridOptions grid;
  grid.cell_m = cell_m;
  grid.x_max_m = on_lattice(x_max);
  grid.y_max_m = on_lattice(y_max);
  grid.x_min_m = grid.x_max_m - cell_m * std::ceil((grid.x_max_m - x_min) / cell_m - 1e-9);
  grid.y_min_m = grid.y_max_m - cell_m * std::ceil((grid.y_max_m - y_min) / cell_m - 1e-9);
  return grid;
}

}  // namespace

std::optional<BevGridOptions> FloorFootprintGrid(const calibration::CameraModel& camera,
                                                 const calibration::CameraMount& mount,
                                                 double cell_m, double max_range_m,
                                                 double max_cells_per_pixel) {
  // Two probes: the square at up to 600 cells a side (2 cm cells up to 6 m),
  // then, where that was coarser, 2 cm cells over what it found plus three of
  // its cells around (at most 1500 cells a side). The coarse probe's
  // resolution test differences over its own cells, inwards at the corners:
  // with one cell around, the simulator's camera lost 4 cm of its far corners.
  constexpr double kProbeCell = 0.02;
  const double max_floor_per_px = max_cells_per_pixel * cell_m;
  const double square_cell = std::max(kProbeCell, 2.0 * max_range_m / 600.0);
  const BevGridOptions square =
      ProbeGrid(mount.forward_m - max_range_m, mount.forward_m + max_range_m,
                mount.lateral_m - max_range_m, mount.lateral_m + max_range_m, square_cell);
  std::optional<BevGridOptions> found =
      ResolvedCellCentres(camera, mount, square, max_floor_per_px);
  if (found && square_cell > kProbeCell) {
    const double fine_cell = std::max(
        kProbeCell,
        std::max(found->x_max_m - found->x_min_m, found->y_max_m - found->y_min_m) / 1500.0);
    const BevGridOptions fine =
        ProbeGrid(std::max(found->x_min_m - 3.0 * square_cell, square.x_min_m),
                  std::min(found->x_max_m + 3.0 * square_cell, square.x_max_m),
                  std::max(found->y_min_m - 3.0 * square_cell, square.y_min_m),
                  std::min(found->y_max_m + 3.0 * square_cell, square.y_max_m), fine_cell);
    found = ResolvedCellCentres(camera, mount, fine, max_floor_per_px);
  }
  if (!found) return std::nullopt;
  // One probe cell, plus 10 cells of floor beyond the seen edge: the ridge
  // filter (sigma 3.5 cells) then sees the fill of unseen cells, not the
  // image border's reflection, within 3 sigma of a marking at the edge.
  const double margin_m = found->cell_m + 10.0 * cell_m;
  BevGridOptions grid;
  grid.cell_m = cell_m;
  grid.x_max_m = std::min(found->x_max_m + margin_m, square.x_max_m);
  grid.y_max_m = std::min(found->y_max_m + margin_m, square.y_max_m);
  grid.x_min_m = std::max(found->x_min_m - margin_m, square.x_min_m);
  grid.y_min_m = std::max(found->y_min_m - margin_m, square.y_min_m);
  return grid;
}

core::Status BevExtent::Validate() const {
  for (const auto& [name, range] : {std::pair{"x_m", x_m}, std::pair{"y_m", y_m}}) {
    if (!range) continue;
    if (!std::isfinite((*range)[0]) || !std::isfinite((*range)[1]) || (*range)[0] >= (*range)[1]) {
      return core::Status::Error(std::string("BEV extent ") + name +
                                 ": expected two finite numbers [min, max] with min < max, got [" +
                                 std::to_string((*range)[0]) + ", " + std::to_string((*range)[1]) +
                                 "]");
    }
  }
  if (!(cell_m > 0.0 && cell_m <= 1.0)) {
    return core::Status::Error("BEV extent cell_m: expected a cell side in (0, 1] m, got " +
                               std::to_string(cell_m));
  }
  if (!(max_range_m > 0.0 && max_range_m <= 100.0)) {
    return core::Status::Error("BEV extent max_range_m: expected (0, 100] m, got " +
                               std::to_string(max_range_m));
  }
  if (!(max_cells_per_pixel > 0.0)) {
    return core::Status::Error("BEV extent max_cells_per_pixel: expected > 0, got " +
                               std::to_string(max_cells_per_pixel));
  }
  return core::Status::Ok();
}

core::Result<BevGridOptions> ResolveBevGrid(const calibration::CameraModel& camera,
                                            const calibration::CameraMount& mount,
                                            const BevExtent& extent) {
  if (core::Status s = extent.Validate(); !s.ok()) return s;
  BevGridOptions grid;
  grid.cell_m = extent.cell_m;
  if (!extent.x_m || !extent.y_m) {
    const std::optional<BevGridOptions> footprint = FloorFootprintGrid(
        camera, mount, extent.cell_m, extent.max_range_m, extent.max_cells_per_pixel);
    if (!footprint) {
      std::ostringstream out;
      out << "BEV extent: the camera sees no floor within " << extent.max_range_m
          << " m of its foot point at one pixel per " << extent.max_cells_per_pixel << " cells of "
          << extent.cell_m
          << " m or finer (check the mount's height and pitch, choose a coarser cell, or give "
             "both ranges, x and y, explicitly)";
      return core::Status::Error(out.str());
    }
    grid = *footprint;
  }
  if (extent.x_m)
    std::tie(grid.x_min_m, grid.x_max_m) = std::pair((*extent.x_m)[0], (*extent.x_m)[1]);
  if (extent.y_m)
    std::tie(grid.y_min_m, grid.y_max_m) = std::pair((*extent.y_m)[0], (*extent.y_m)[1]);
  const double rows = (grid.x_max_m - grid.x_min_m) / grid.cell_m,
               cols = (grid.y_max_m - grid.y_min_m) / grid.cell_m;
  if (rows > kMaxCellsPerSide || cols > kMaxCellsPerSide || rows < 1.0 || cols < 1.0) {
    return core::Status::Error(
        "BEV extent: x " + std::to_string(grid.x_min_m) + ".." + std::to_string(grid.x_max_m) +
        " m, y " + std::to_string(grid.y_min_m) + ".." + std::to_string(grid.y_max_m) + " m at " +
        std::to_string(grid.cell_m) + " m cells is " +
        std::to_string(static_cast<long>(std::lround(rows))) + " x " +
        std::to_string(static_cast<long>(std::lround(cols))) +
        " cells; expected 1..4096 per side (choose a coarser cell or smaller ranges)");
  }
  // Whether the camera sees any of it: a probe at the grid's extent, 2 cm cells at most.
  BevRemap::Options check;
  check.fill_unseen = false;
  check.grid = grid;
  check.grid.cell_m = std::max(
      grid.cell_m,
      std::min(0.02, 0.5 * std::min(grid.x_max_m - grid.x_min_m, grid.y_max_m - grid.y_min_m)));
  if (const BevRemap probe(camera, mount, check); probe.valid_cells() == 0) {
    return core::Status::Error("BEV extent: the camera sees none of the floor in x " +
                               std::to_string(grid.x_min_m) + ".." + std::to_string(grid.x_max_m) +
                               " m, y " + std::to_string(grid.y_min_m) + ".." +
                               std::to_string(grid.y_max_m) + " m");
  }
  return grid;
}

void WarpToBevPinhole(const cv::Mat& image, const BevGrid& grid,
                      const calibration::CameraMount& mount, const Eigen::Matrix3d& K,
                      cv::Mat* bev) {
  assert(bev != nullptr);
  const Eigen::Matrix3d M = PinholeImageFromCell(grid, mount, K);
  cv::Matx33d M_cv;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) M_cv(r, c) = M(r, c);
  }
  cv::warpPerspective(image, *bev, M_cv, cv::Size(grid.cols(), grid.rows()),
                      cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT,
                      cv::Scalar::all(0));
}

}  // namespace groundline::perception
