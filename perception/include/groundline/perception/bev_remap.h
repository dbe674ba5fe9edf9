// Inverse perspective mapping (IPM): a metric bird's-eye-view (BEV) image of
// the floor, made from a camera frame by one precomputed remap table that
// undistorts (through the real lens model) and rectifies in a single pass.
//
// The BEV grid (BevGrid) covers the floor rectangle [x_min, x_max] x
// [y_min, y_max] of base_link (docs/conventions.md: x forward, y left, floor
// z = 0), metres, with square cells of cell_m. The image is laid out the way a
// driver sees the floor from above: row 0 is the far edge (x_max), column 0 the
// left edge (y_max). Cell (col, row) has its centre at
//
//   x = x_max - (row + 0.5) cell_m,   y = y_max - (col + 0.5) cell_m,
//
// so rows run against base x and columns against base y; continuous cell
// coordinates follow the pixel convention of camera_model.h (integer values at
// cell centres). Hence d/dcol = -cell_m d/dy and d/drow = -cell_m d/dx.
//
// Why the default extent is x 0.6-2.4 m, y +-1.0 m (issue 4 asked 0.6-4.2 m,
// +-2 m): the reference camera (CameraMount defaults: 0.58 m high, pitched
// 42.4 deg down, 0.42 m ahead of the axle; fx = 1132 px on 1280 x 1024) sees
// the floor only from about 0.67 m to 2.2 m ahead (the image's bottom and top
// rows), and about +-0.35 m across at the near edge to +-1.0 m at the far
// edge. Cells the camera does not see are flagged invalid (valid_mask); a
// larger extent only costs time. Every extent is an Option.
//
// The remap table (BevRemap), seed paper eqs. (29)-(33) but through the lens
// model instead of an ideal pinhole: for each cell centre (x, y, 0),
//   p_cam = R_cam_base (x, y, 0)^T + t_cam_base,   (u, v) = project(p_cam)
// (CameraModel::ProjectBatch, mrcal). A cell is valid when p_cam is in front
// of the camera and (u, v) lies in [0, width-1] x [0, height-1], where
// bilinear interpolation needs no pixel outside the image. Invalid cells hold
// the map value (-1, -1) in pixel_map(); in the BEV they take the grey of the
// nearest valid cell (Options::fill_unseen: the remap reads that cell's pixel
// there), or are 0 (the remap reads pixel (0, 0) and zeroes them after: 5x
// faster than letting cv::remap handle out-of-image map entries). Apply() is cv::remap,
// bilinear, on the fixed-point maps (cv::convertMaps: 1/32 px interpolation
// steps) or on the float maps (Options::fixed_point = false).
//
// The pinhole baseline (WarpToBevPinhole): the plane-induced homography
// H_img_floor = K [r1 r2 t] (camera_extrinsics.h, seed paper eq. 30) composed
// with the cell -> floor affine A_floor_cell, one cv::warpPerspective. It
// ignores lens distortion; for LENSMODEL_PINHOLE it agrees with BevRemap.
//
// Thread-safety: BevGrid is an immutable value. A BevRemap is safe for
// concurrent const use (Apply); Rebuild must not run concurrently with
// anything else on the same object.
#ifndef GROUNDLINE_PERCEPTION_BEV_REMAP_H_
#define GROUNDLINE_PERCEPTION_BEV_REMAP_H_

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::perception {

struct BevGridOptions {
  double x_min_m = 0.6;   // near edge, ahead of base_link
  double x_max_m = 2.4;   // far edge
  double y_min_m = -1.0;  // right edge
  double y_max_m = 1.0;   // left edge
  double cell_m = 0.01;   // square cell side

  // Ok when all values are finite, cell_m > 0, x_max_m > x_min_m,
  // y_max_m > y_min_m and the grid has at most 4096 cells per side.
  core::Status Validate() const;
};

class BevGrid {
 public:
  // The options must be valid (asserted). rows = round((x_max - x_min) /
  // cell), cols = round((y_max - y_min) / cell); x_min and y_min are then
  // implied by x_max, y_max, rows, cols and cell.
  explicit BevGrid(const BevGridOptions& options);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  double cell_m() const { return options_.cell_m; }
  const BevGridOptions& options() const { return options_; }

  // Floor point (x, y) in base_link, metres, of the continuous cell
  // coordinates (col, row).
  Eigen::Vector2d FloorPointOfCell(const Eigen::Vector2d& cell) const;
  // Continuous cell coordinates (col, row) of the floor point (x, y), metres.
  Eigen::Vector2d CellOfFloorPoint(const Eigen::Vector2d& floor_point_m) const;
  // The affine A_floor_cell: (x, y, 1)^T = A (col, row, 1)^T.
  Eigen::Matrix3d FloorFromCell() const;

 private:
  BevGridOptions options_;
  int rows_ = 0;
  int cols_ = 0;
};

class BevRemap {
 public:
  struct Options {
    BevGridOptions grid;
    bool fixed_point = true;  // Apply() on CV_16SC2 + CV_16UC1 maps (faster)
    // Anti-aliasing: each cell is the mean (cv::INTER_AREA) of supersampling^2
    // bilinear samples at its sub-cell centres (1: one sample at the centre).
    // Without it, a marking narrower than a cell (an 8 mm joint at 1 cm cells)
    // falls between the samples wherever it runs along the grid. The sub-cell
    // pixel positions are bilinear interpolations of the cell-centre table
    // (the projection is smooth on the scale of a cell).
    int supersampling = 1;
    // Samples per cell across (along the grid's columns, base_link y) when
    // more are needed there than along (0: supersampling). The camera looks
    // down at a grazing angle, so its pixels are 3-4x finer across than along
    // the floor 1-2.5 m ahead (2.6 mm x 9 mm at 2 m): with 2 samples per 1 cm
    // cell a sharp tape edge running along the grid steps in 5 mm jumps, the
    // centre of a 10 cm tape in 2.5 mm ones (its error a sawtooth of the
    // sub-cell phase, the same along the whole line). 4 across x 2 along
    // costs half of what 4 x 4 does.
    int supersampling_across = 0;
    // The sampling of groundline extract and localize: 2 samples along x, 4
    // across (the rest default).
    static Options ForLineExtraction() {
      Options options;
      options.supersampling = 2;
      options.supersampling_across = 4;
      return options;
    }
    // The sampling of the floor texture's tracking (floor_texture_flow.h):
    // 4 mm cells, 2 x 2 samples each. Lucas-Kanade on 1 cm cells reads a
    // shift biased towards whole cells, by up to 0.07 cell, alike for every
    // patch: a vehicle at constant speed moves the floor by the same
    // fraction of a cell in every frame pair, and the common bias is read as
    // a scale (a camera height off by up to a millimetre for minutes). At
    // 4 mm the bias is within +-0.05 mm per 27 cm frame step, and four times
    // as many patches pass the forward-backward check
    // (docs/2026-12-07-texture-tracking-cells.md).
    static Options ForTextureTracking() {
      Options options;
      options.grid.cell_m = 0.004;
      options.supersampling = 2;
      return options;
    }
    int SamplesAcross() const {
      return supersampling_across > 0 ? supersampling_across : supersampling;
    }
    // Cells the camera does not see take the grey of the nearest seen cell
    // (their map entry is that cell's, found once per Rebuild by a distance
    // transform), so the ridge filter near the footprint's border sees floor
    // on both sides instead of a black step: a joint 1 cm inside the far
    // border was found 8 mm off and then dropped. false: they are 0.
    bool fill_unseen = true;
    core::Status Validate() const;
  };

  // Builds the table for the camera on the mount; both options and mount must
  // be valid (asserted; validate them at the edge).
  BevRemap(calibration::CameraModel camera, const calibration::CameraMount& mount,
           const Options& options);

  // Recomputes the table for a new mount (e.g. self-calibrated pitch or
  // height), reusing the precomputed floor points of the cell centres: one
  // rigid transform and one batched projection per cell.
  void Rebuild(const calibration::CameraMount& mount);

  // The BEV of a camera frame (rows() x cols(), same type as image; any depth
  // and channel count cv::remap supports). image must be width x height of the
  // camera (asserted).
  void Apply(const cv::Mat& image, cv::Mat* bev) const;

  const BevGrid& grid() const { return grid_; }
  const calibration::CameraModel& camera() const { return camera_; }
  const calibration::CameraMount& mount() const { return mount_; }
  // Pixel (u, v) of each cell centre, CV_32FC2, rows() x cols(); (-1, -1) where
  // invalid.
  const cv::Mat& pixel_map() const { return pixel_map_; }
  // 255 where the cell is valid, 0 elsewhere; CV_8UC1, rows() x cols().
  const cv::Mat& valid_mask() const { return valid_mask_; }
  int valid_cells() const { return valid_cells_; }

 private:
  bool Supersampled() const { return options_.supersampling > 1 || options_.SamplesAcross() > 1; }
  calibration::CameraModel camera_;
  calibration::CameraMount mount_;
  Options options_;
  BevGrid grid_;
  Eigen::Matrix3Xd floor_points_base_;  // 3 x (rows cols), cell centres, row-major
  Eigen::Matrix3Xd points_cam_;         // scratch for Rebuild
  Eigen::Matrix2Xd pixels_;             // scratch for Rebuild
  std::vector<std::uint8_t> projected_;
  cv::Mat pixel_map_;
  cv::Mat valid_mask_;
  cv::Mat invalid_mask_;    // 255 - valid_mask_
  cv::Mat remap_map_;       // pixel_map_ with (0, 0) in invalid cells (fast cv::remap)
  cv::Mat fixed_map_xy_;    // CV_16SC2
  cv::Mat fixed_map_frac_;  // CV_16UC1
  cv::Mat fine_map_xy_;     // supersampled fixed-point maps (Supersampled())
  cv::Mat fine_map_frac_;
  int valid_cells_ = 0;

  void FillUnseenFromNearestSeen();
};

// M_img_cell = H_img_floor(T_base_cam, K) * A_floor_cell: maps BEV cell
// coordinates (col, row, 1) to ideal-pinhole pixels (homogeneous).
Eigen::Matrix3d PinholeImageFromCell(const BevGrid& grid, const calibration::CameraMount& mount,
                                     const Eigen::Matrix3d& K);

// The grid (cell_m cells) over the floor the camera actually sees: the
// bounding box, plus one probe cell and 10 cells (room for the ridge filter at
// the edge), of the centres of the 2 cm probe cells it sees within the square
// +-max_range_m around its foot point (mount forward_m, lateral_m), clipped to
// that square, where it resolves the floor: one pixel covers at most
// max_cells_per_pixel cells (the larger axis of its floor footprint). The
// square is first probed at up to 600 cells a side, then what that found at
// 2 cm. The reference camera resolves all it sees (9 mm per pixel along the
// floor 2.2 m ahead); a low camera looking towards the horizon (a Duckiebot's,
// 0.1 m high) sees floor to the horizon but resolves it over the first metre
// only; a car's camera 1.6 m high sees the road from 6 m on, resolved at 3 cm
// cells to about 10 m. Nothing resolved: nullopt.
std::optional<BevGridOptions> FloorFootprintGrid(const calibration::CameraModel& camera,
                                                 const calibration::CameraMount& mount,
                                                 double cell_m = 0.01, double max_range_m = 30.0,
                                                 double max_cells_per_pixel = 3.0);

// The BEV's extent as a user states it (groundline extract's --bev-x, --bev-y
// and --bev-cell; the service's localizer.bev): a range given replaces the
// camera's floor footprint (FloorFootprintGrid) along its axis, one not given
// takes the footprint's. The ridge filter's scale and the extractor's other
// lengths in cells scale with cell_m (docs/perception.md).
struct BevExtent {
  std::optional<std::array<double, 2>> x_m;  // [near, far] along base_link x, metres
  std::optional<std::array<double, 2>> y_m;  // [right, left] along base_link y, metres
  double cell_m = 0.01;
  // The footprint (FloorFootprintGrid): its probe's range and resolution.
  double max_range_m = 30.0;
  double max_cells_per_pixel = 3.0;

  // Names the field: ranges finite with min < max, cell_m in (0, 1],
  // max_range_m in (0, 100], max_cells_per_pixel > 0.
  core::Status Validate() const;
};

// The grid of an extent on this camera and mount. Errors: an invalid extent; an
// axis to be taken from the footprint when the camera sees no floor within
// max_range_m; a grid of more than 4096 cells per side (the message gives the
// size and asks for a coarser cell or a smaller range); a grid in which the
// camera sees no floor cell.
core::Result<BevGridOptions> ResolveBevGrid(const calibration::CameraModel& camera,
                                            const calibration::CameraMount& mount,
                                            const BevExtent& extent);

// The pinhole baseline: cv::warpPerspective(image, bev, M_img_cell, grid size,
// INTER_LINEAR | WARP_INVERSE_MAP, BORDER_CONSTANT 0). Lens distortion ignored.
void WarpToBevPinhole(const cv::Mat& image, const BevGrid& grid,
                      const calibration::CameraMount& mount, const Eigen::Matrix3d& K,
                      cv::Mat* bev);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_BEV_REMAP_H_
