#include "groundline/calibration/floor_rectification.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace groundline::calibration {
namespace {

// The box of normalized image coordinates (x/z, y/z) the imager border sees,
// enlarged by 5 %: points outside it are not taken even when a polynomial lens
// model folds them back into the image.
Eigen::Vector4d NormalizedBounds(const CameraModel& camera) {
  const double w = camera.width_px() - 0.5, h = camera.height_px() - 0.5;
  double lo_x = std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  for (int i = 0; i <= 8; ++i) {
    const double t = i / 8.0;
    for (const Eigen::Vector2d& px :
         {Eigen::Vector2d(-0.5 + t * (w + 0.5), -0.5), Eigen::Vector2d(-0.5 + t * (w + 0.5), h),
          Eigen::Vector2d(-0.5, -0.5 + t * (h + 0.5)), Eigen::Vector2d(w, -0.5 + t * (h + 0.5))}) {
      const core::Result<Eigen::Vector3d> ray = camera.Unproject(px, RayNormalization::kZEqualsOne);
      if (!ray.ok()) continue;
      lo_x = std::min(lo_x, ray->x());
      hi_x = std::max(hi_x, ray->x());
      lo_y = std::min(lo_y, ray->y());
      hi_y = std::max(hi_y, ray->y());
    }
  }
  const double mx = 0.05 * (hi_x - lo_x), my = 0.05 * (hi_y - lo_y);
  return {lo_x - mx, hi_x + mx, lo_y - my, hi_y + my};
}

double Bilinear(const FloorImageView& im, const Eigen::Vector2d& px) {
  const double u = std::clamp(px.x(), 0.0, im.width_px - 1.0);
  const double v = std::clamp(px.y(), 0.0, im.height_px - 1.0);
  const int u0 = std::min(static_cast<int>(u), im.width_px - 2);
  const int v0 = std::min(static_cast<int>(v), im.height_px - 2);
  const double a = u - u0, b = v - v0;
  const std::uint8_t* r0 = im.grey + static_cast<std::ptrdiff_t>(v0) * im.stride + u0;
  const std::uint8_t* r1 = r0 + im.stride;
  return (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
}

}  // namespace

core::Status FloorRectificationOptions::Validate() const {
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) {
    return core::Status::Error("FloorRectificationOptions.resolution_m: expected > 0");
  }
  if (max_side_px < 16) {
    return core::Status::Error("FloorRectificationOptions.max_side_px: expected >= 16");
  }
  return core::Status::Ok();
}

Eigen::Vector2d FloorRaster::RasterOfFloor(const Eigen::Vector2d& floor_m) const {
  return {(max_corner_m.y() - floor_m.y()) / resolution_m,
          (max_corner_m.x() - floor_m.x()) / resolution_m};
}

Eigen::Vector2d FloorRaster::FloorOfRaster(const Eigen::Vector2d& raster) const {
  return {max_corner_m.x() - raster.y() * resolution_m,
          max_corner_m.y() - raster.x() * resolution_m};
}

core::Result<FloorRaster> RectifyFloor(const CameraModel& camera, const CameraMount& mount,
                                       const std::vector<FloorImageView>& images,
                                       const Eigen::Vector2d& min_corner_m,
                                       const Eigen::Vector2d& max_corner_m,
                                       const FloorRectificationOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  if (core::Status s = mount.Validate(); !s.ok()) return s.WithContext("floor rectification");
  const Eigen::Vector2d extent = max_corner_m - min_corner_m;
  if (!(extent.minCoeff() > 0.0) || !extent.allFinite()) {
    return core::Status::Error("floor rectification: empty floor rectangle");
  }
  for (const FloorImageView& im : images) {
    if (im.grey == nullptr || im.width_px != camera.width_px() ||
        im.height_px != camera.height_px() || im.stride < im.width_px) {
      return core::Status::Error("floor rectification: an image is not " +
                                 std::to_string(camera.width_px()) + "x" +
                                 std::to_string(camera.height_px()) + " 8-bit grey");
    }
  }
  FloorRaster raster;
  raster.max_corner_m = max_corner_m;
  raster.resolution_m = std::max(options.resolution_m, extent.maxCoeff() / options.max_side_px);
  raster.width_px = std::max(1, static_cast<int>(std::ceil(extent.y() / raster.resolution_m)));
  raster.height_px = std::max(1, static_cast<int>(std::ceil(extent.x() / raster.resolution_m)));
  raster.grey.assign(static_cast<std::size_t>(raster.width_px) * raster.height_px, 0);
  std::vector<float> best_r2(raster.grey.size(), std::numeric_limits<float>::infinity());

  const Eigen::Vector4d bounds = NormalizedBounds(camera);
  const Eigen::Matrix3d K = camera.K();
  const Eigen::Isometry3d T_cam_base = BaseFromCamera(mount).inverse();
  Eigen::Matrix3Xd points(3, raster.width_px);
  Eigen::Matrix2Xd pixels;
  std::vector<std::uint8_t> valid;
  for (const FloorImageView& im : images) {
    const core::SE2 T_base_floor = im.T_floor_base.Inverse();
    for (int r = 0; r < raster.height_px; ++r) {
      for (int c = 0; c < raster.width_px; ++c) {
        const Eigen::Vector2d floor = raster.FloorOfRaster({c + 0.5, r + 0.5});
        const Eigen::Vector2d base = T_base_floor * floor;
        points.col(c) = T_cam_base * Eigen::Vector3d(base.x(), base.y(), 0.0);
      }
      camera.ProjectBatch(points, &pixels, &valid);
      for (int c = 0; c < raster.width_px; ++c) {
        const Eigen::Vector3d& p = points.col(c);
        if (!valid[c] || p.z() <= 0.0) continue;
        const double nx = p.x() / p.z(), ny = p.y() / p.z();
        if (nx < bounds[0] || nx > bounds[1] || ny < bounds[2] || ny > bounds[3]) continue;
        const Eigen::Vector2d px = pixels.col(c);
        if (!camera.InImage(px)) continue;
        const std::size_t cell = static_cast<std::size_t>(r) * raster.width_px + c;
        const float r2 = static_cast<float>((px - K.block<2, 1>(0, 2)).squaredNorm());
        if (r2 >= best_r2[cell]) continue;
        best_r2[cell] = r2;
        raster.grey[cell] =
            static_cast<std::uint8_t>(std::clamp(std::lround(Bilinear(im, px)), 1L, 255L));
      }
    }
  }
  return raster;
}

}  // namespace groundline::calibration
