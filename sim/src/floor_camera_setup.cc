// Floor camera options and the pixel-to-floor table (one unprojection per pixel).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "floor_camera_internal.h"
#include "options_check.h"

namespace groundline::sim {

using internal::CheckRange;
using internal::FirstError;

core::Status FloorCameraOptions::Validate() const {
  const char* o = "FloorCameraOptions";
  core::Status s = FirstError({
      CheckRange(o, "width_px", width_px, 16, 16384),
      CheckRange(o, "height_px", height_px, 16, 16384),
      CheckRange(o, "focal_px", focal_px, 1.0, 1e5),
      CheckRange(o, "principal_offset_px[0]", principal_offset_px[0], -0.25 * width_px,
                 0.25 * width_px),
      CheckRange(o, "principal_offset_px[1]", principal_offset_px[1], -0.25 * height_px,
                 0.25 * height_px),
      CheckRange(o, "sensor_rate_hz", sensor_rate_hz, 0.1, 1000.0),
  });
  if (!s.ok()) return s;
  for (const double d : distortion) {
    if (!(std::abs(d) <= 1.0)) return CheckRange(o, "distortion", d, -1.0, 1.0);
  }
  if (core::Status m = mount.Validate(); !m.ok()) return m.WithContext("FloorCameraOptions.mount");
  return core::Status::Ok();
}

core::Result<calibration::CameraModel> FloorCameraOptions::MakeCameraModel() const {
  if (core::Status s = Validate(); !s.ok()) return s;
  const double cx = 0.5 * (width_px - 1) + principal_offset_px[0];
  const double cy = 0.5 * (height_px - 1) + principal_offset_px[1];
  std::vector<double> intrinsics = {focal_px, focal_px, cx, cy};
  intrinsics.insert(intrinsics.end(), distortion.begin(), distortion.end());
  return calibration::CameraModel::Create("LENSMODEL_OPENCV5", std::move(intrinsics), width_px,
                                          height_px);
}

namespace internal {

core::Result<PixelFloorTable> BuildPixelFloorTable(const calibration::CameraModel& camera,
                                                   const calibration::CameraMount& mount,
                                                   double max_floor_range_m) {
  const int w = camera.width_px();
  const int h = camera.height_px();
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  Eigen::Matrix2Xd pixels(2, static_cast<Eigen::Index>(n));
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      pixels.col(static_cast<Eigen::Index>(v) * w + u) << u, v;
    }
  }
  Eigen::Matrix3Xd rays;
  std::vector<std::uint8_t> ray_ok;
  camera.UnprojectBatch(pixels, calibration::RayNormalization::kUnitNorm, &rays, &ray_ok);

  const Eigen::Isometry3d T_base_cam = calibration::BaseFromCamera(mount);
  const Eigen::Matrix3d R = T_base_cam.linear();
  const Eigen::Vector3d t = T_base_cam.translation();
  PixelFloorTable table;
  table.width_px = w;
  table.height_px = h;
  for (auto* f :
       {&table.x_m, &table.y_m, &table.dxu, &table.dyu, &table.dxv, &table.dyv, &table.foot_m}) {
    f->assign(n, 0.0f);
  }
  table.valid.assign(n, 0);
  std::vector<double> px(n), py(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!ray_ok[i]) continue;
    const Eigen::Vector3d d = R * rays.col(static_cast<Eigen::Index>(i));
    if (d.z() >= -1e-9) continue;
    const double lambda = -t.z() / d.z();
    const Eigen::Vector3d p = t + lambda * d;
    if ((p - t).head<2>().norm() > max_floor_range_m) continue;
    px[i] = p.x();
    py[i] = p.y();
    table.valid[i] = 1;
  }
  // Central differences (one-sided at the border or next to the wall).
  const auto diff = [&](int u, int v, int du, int dv, double* gx, double* gy) {
    const auto idx = [w](int uu, int vv) { return static_cast<std::size_t>(vv) * w + uu; };
    const int u0 = std::max(0, u - du), v0 = std::max(0, v - dv);
    const int u1 = std::min(w - 1, u + du), v1 = std::min(h - 1, v + dv);
    std::size_t i0 = idx(u0, v0), i1 = idx(u1, v1);
    if (!table.valid[i0]) i0 = idx(u, v);
    if (!table.valid[i1]) i1 = idx(u, v);
    const double steps = (du ? (i1 % w) - static_cast<double>(i0 % w)
                             : static_cast<double>(i1 / w) - static_cast<double>(i0 / w));
    if (steps == 0.0) {
      *gx = *gy = 0.0;
      return;
    }
    *gx = (px[i1] - px[i0]) / steps;
    *gy = (py[i1] - py[i0]) / steps;
  };
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      if (!table.valid[i]) continue;
      double gx, gy;
      table.x_m[i] = static_cast<float>(px[i]);
      table.y_m[i] = static_cast<float>(py[i]);
      diff(u, v, 1, 0, &gx, &gy);
      table.dxu[i] = static_cast<float>(gx);
      table.dyu[i] = static_cast<float>(gy);
      diff(u, v, 0, 1, &gx, &gy);
      table.dxv[i] = static_cast<float>(gx);
      table.dyv[i] = static_cast<float>(gy);
      table.foot_m[i] =
          0.5f * (std::hypot(table.dxu[i], table.dyu[i]) + std::hypot(table.dxv[i], table.dyv[i]));
      ++table.floor_pixels;
    }
  }
  if (table.floor_pixels == 0) {
    return core::Status::Error("floor camera: no pixel sees the floor within " +
                               std::to_string(max_floor_range_m) +
                               " m (check the mount's height and pitch)");
  }
  constexpr int kT = PixelFloorTable::kTile;
  table.tiles_x = (w + kT - 1) / kT;
  table.tiles_y = (h + kT - 1) / kT;
  for (int ty = 0; ty < table.tiles_y; ++ty) {
    for (int tx = 0; tx < table.tiles_x; ++tx) {
      double lo_x = 1e300, lo_y = 1e300, hi_x = -1e300, hi_y = -1e300, foot = 0.0;
      for (int v = ty * kT; v < std::min(h, (ty + 1) * kT); ++v) {
        for (int u = tx * kT; u < std::min(w, (tx + 1) * kT); ++u) {
          const std::size_t i = static_cast<std::size_t>(v) * w + u;
          if (!table.valid[i]) continue;
          lo_x = std::min(lo_x, px[i]);
          hi_x = std::max(hi_x, px[i]);
          lo_y = std::min(lo_y, py[i]);
          hi_y = std::max(hi_y, py[i]);
          foot = std::max<double>(foot, std::hypot(table.dxu[i], table.dyu[i]) +
                                            std::hypot(table.dxv[i], table.dyv[i]));
        }
      }
      const bool any = lo_x <= hi_x;
      table.tile_cx_m.push_back(any ? static_cast<float>(0.5 * (lo_x + hi_x)) : 0.0f);
      table.tile_cy_m.push_back(any ? static_cast<float>(0.5 * (lo_y + hi_y)) : 0.0f);
      table.tile_radius_m.push_back(
          any ? static_cast<float>(0.5 * std::hypot(hi_x - lo_x, hi_y - lo_y) + foot) : -1.0f);
    }
  }
  return table;
}

}  // namespace internal
}  // namespace groundline::sim
