// The rectified floor: a bird's-eye raster of the floor built from one or more
// camera images through a solved mount, for the commissioning report's check
// that the tags land on their surveyed outlines.
//
// Raster geometry (the floor seen from above, floor x up, floor y to the left,
// as in the report's plots). Cell (row r, column c) covers the floor point, in
// the layout's frame (metres),
//   x = x_max_m - (r + 0.5) resolution_m,   y = y_max_m - (c + 0.5) resolution_m.
// Each cell is seen through each image i at the pixel
//   pixel_i = project(R_cam_base (T_floor_base_i^-1 (x, y), 0) + t_cam_base)
// (floor_projection.h); the cell takes the bilinear grey value of the image
// where that pixel lies closest to the principal point (the sharpest, least
// distorted view), and 0 where no image sees it.
//
// Units: metres on the floor, pixels in the images (camera_model.h
// convention, pixel centres at integers). Pure functions; thread-safe.
#ifndef GROUNDLINE_CALIBRATION_FLOOR_RECTIFICATION_H_
#define GROUNDLINE_CALIBRATION_FLOOR_RECTIFICATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct FloorRectificationOptions {
  double resolution_m = 0.0025;  // floor edge of one raster cell
  int max_side_px = 1200;        // the resolution is coarsened to keep both sides below this

  core::Status Validate() const;
};

// One 8-bit grey image (row-major, `stride` bytes per row, not owned) and the
// base_link pose in the layout's frame when it was taken.
struct FloorImageView {
  const std::uint8_t* grey = nullptr;
  int width_px = 0;
  int height_px = 0;
  int stride = 0;
  core::SE2 T_floor_base;
};

struct FloorRaster {
  Eigen::Vector2d max_corner_m = Eigen::Vector2d::Zero();  // (x_max_m, y_max_m)
  double resolution_m = 0.0;
  int width_px = 0;                // columns, along -y
  int height_px = 0;               // rows, along -x
  std::vector<std::uint8_t> grey;  // row-major, width_px per row; 0 = not seen

  // The raster position (column, row as continuous coordinates, cell centres
  // at +0.5) of a floor point, and back.
  Eigen::Vector2d RasterOfFloor(const Eigen::Vector2d& floor_m) const;
  Eigen::Vector2d FloorOfRaster(const Eigen::Vector2d& raster) const;
};

// Rectifies the floor rectangle [min_corner_m, max_corner_m] (layout frame).
// Fails when the rectangle is empty or an image does not match the camera's
// size. Images must be 8-bit grey of camera.width_px() x camera.height_px().
core::Result<FloorRaster> RectifyFloor(const CameraModel& camera, const CameraMount& mount,
                                       const std::vector<FloorImageView>& images,
                                       const Eigen::Vector2d& min_corner_m,
                                       const Eigen::Vector2d& max_corner_m,
                                       const FloorRectificationOptions& options);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_FLOOR_RECTIFICATION_H_
