// The commissioning scene: a tag mat on the floor seen from a few vehicle poses.
#include "groundline/sim/commissioning_scene.h"

#include <cassert>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/tag_detection.h"
#include "groundline/core/atomic_file.h"
#include "options_check.h"

namespace groundline::sim {

using internal::CheckRange;
using internal::FirstError;

FloorCameraOptions CommissioningOptions::DefaultCamera() {
  FloorCameraOptions c;
  c.mount.height_m = 0.5853;
  c.mount.pitch_rad = 41.9 * std::numbers::pi / 180.0;
  c.mount.roll_rad = 0.6 * std::numbers::pi / 180.0;
  c.mount.yaw_rad = -0.8 * std::numbers::pi / 180.0;
  c.mount.forward_m = 0.4162;
  c.mount.lateral_m = 0.0115;
  return c;
}

FloorRenderOptions CommissioningOptions::DefaultRender() {
  FloorRenderOptions r;  // texture, light gradient, motion blur and noise stay on
  r.supersampling = 6;
  r.scuffs = r.oil = r.glare = r.shadows = false;
  r.wear = false;
  return r;
}

CommissioningOptions CommissioningOptions::Small() {
  CommissioningOptions o;
  o.camera.width_px = 480;
  o.camera.height_px = 384;
  o.camera.focal_px = 425.0;
  o.camera.principal_offset_px = {1.5, -1.0};
  o.camera.mount.pitch_rad = 52.0 * std::numbers::pi / 180.0;
  o.render.supersampling = 3;
  o.tag_rows = 6;
  o.tag_cols = 4;
  o.tag_size_m = 0.2;
  o.tag_pitch_m = 0.3;
  o.mat_origin_m = Vector2(0.5, -0.45);
  o.poses = 5;
  o.start_x_m = -0.3;
  o.step_x_m = 0.25;
  return o;
}

core::Status CommissioningOptions::Validate() const {
  const char* o = "CommissioningOptions";
  core::Status s = FirstError({
      CheckRange(o, "tag_rows", tag_rows, 1, 100),
      CheckRange(o, "tag_cols", tag_cols, 1, 100),
      CheckRange(o, "tag_size_m", tag_size_m, 0.01, 2.0),
      CheckRange(o, "tag_pitch_m", tag_pitch_m, tag_size_m * 1.25, 10.0),
      CheckRange(o, "first_tag_id", first_tag_id, 0,
                 calibration::Tag36h11Count() - tag_rows * tag_cols),
      CheckRange(o, "poses", poses, 1, 1000),
      CheckRange(o, "step_x_m", step_x_m, -10.0, 10.0),
      CheckRange(o, "lateral_jitter_m", lateral_jitter_m, 0.0, 2.0),
      CheckRange(o, "yaw_jitter_rad", yaw_jitter_rad, 0.0, 1.0),
      CheckRange(o, "speed_mps", speed_mps, 0.0, 3.0),
  });
  if (!s.ok()) return s;
  if (core::Status c = camera.Validate(); !c.ok()) return c;
  return render.Validate();
}

World TagMatWorld(const calibration::TagLayout& layout) {
  World world;
  world.name = "commissioning tag mat";
  Vector2 lo(1e300, 1e300), hi(-1e300, -1e300);
  const auto add = [&world](const core::SE2& T, double x0, double x1, double y, double width,
                            MarkingColour colour) {
    FloorMarking m;
    m.colour = colour;
    m.polarity =
        colour == MarkingColour::kWhite ? MarkingPolarity::kBright : MarkingPolarity::kDark;
    m.polyline_m = {T * Vector2(x0, y), T * Vector2(x1, y)};
    m.width_m = width;
    world.markings.push_back(std::move(m));
  };
  for (const calibration::SurveyedTag& tag : layout.tags) {
    const calibration::TagPattern p = calibration::Tag36h11Pattern(tag.id).value();
    const double cell = tag.size_m / p.width_at_border;
    const double half = 0.5 * p.total_width * cell;
    add(tag.T_frame_tag, -half, half, 0.0, 2.0 * half, MarkingColour::kWhite);
    for (int r = 0; r < p.total_width; ++r) {
      const double y = half - (r + 0.5) * cell;  // row 0 at the top (+y)
      for (int c = 0; c < p.total_width;) {
        if (!p.Black(r, c)) {
          ++c;
          continue;
        }
        int end = c;
        while (end < p.total_width && p.Black(r, end)) ++end;
        add(tag.T_frame_tag, -half + c * cell, -half + end * cell, y, cell, MarkingColour::kGroove);
        c = end;
      }
    }
    lo = lo.cwiseMin(tag.T_frame_tag.translation());
    hi = hi.cwiseMax(tag.T_frame_tag.translation());
  }
  world.floor_min_m = lo - Vector2(5.0, 5.0);
  world.floor_max_m = hi + Vector2(5.0, 5.0);
  return world;
}

core::Result<CommissioningScene> MakeCommissioningScene(const CommissioningOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  core::Result<calibration::CameraModel> camera = options.camera.MakeCameraModel();
  if (!camera.ok()) return camera.status();
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  calibration::TagLayout layout;
  layout.frame = calibration::TagLayoutFrame::kFloor;
  for (int r = 0; r < options.tag_rows; ++r) {
    for (int c = 0; c < options.tag_cols; ++c) {
      calibration::SurveyedTag tag;
      tag.id = options.first_tag_id + r * options.tag_cols + c;
      tag.size_m = options.tag_size_m;
      tag.T_frame_tag = core::SE2(options.mat_origin_m + options.tag_pitch_m * Vector2(r, c),
                                  std::numbers::pi * unit(rng));
      layout.tags.push_back(tag);
    }
  }
  for (int k = 0; k < options.poses; ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "pose_%03d.png", k);
    // One draw per statement, in core::DrawVector's order.
    const double yaw_rad = options.yaw_jitter_rad * unit(rng);
    const double y_m = options.lateral_jitter_m * unit(rng);
    layout.vehicle_poses.push_back(
        {name, core::SE2(options.start_x_m + k * options.step_x_m, y_m, yaw_rad)});
  }
  CommissioningScene scene{layout, *camera, options.camera.mount, TagMatWorld(layout)};
  return scene;
}

core::Result<std::vector<GreyImage>> RenderCommissioningImages(
    const CommissioningScene& scene, const CommissioningOptions& options) {
  core::Result<FloorRenderer> renderer =
      FloorRenderer::Create(scene.world, scene.camera, scene.true_mount, options.render);
  if (!renderer.ok()) return renderer.status().WithContext("commissioning scene");
  std::vector<GreyImage> images;
  for (std::size_t k = 0; k < scene.layout.vehicle_poses.size(); ++k) {
    images.push_back(renderer->Render(scene.layout.vehicle_poses[k].T_floor_base,
                                      BaseVelocity{options.speed_mps, 0.0}, k));
  }
  return images;
}

core::Status WriteCommissioningScene(const CommissioningScene& scene,
                                     const std::vector<GreyImage>& images,
                                     const std::filesystem::path& dir) {
  assert(images.size() == scene.layout.vehicle_poses.size());
  std::error_code ec;
  std::filesystem::create_directories(dir / "images", ec);
  if (ec) return core::Status::Error((dir / "images").string() + ": " + ec.message());
  for (std::size_t k = 0; k < images.size(); ++k) {
    const GreyImage& im = images[k];
    const cv::Mat mat(im.height_px, im.width_px, CV_8UC1,
                      const_cast<std::uint8_t*>(im.pixels.data()));
    std::vector<std::uint8_t> png;
    const std::filesystem::path path = dir / "images" / scene.layout.vehicle_poses[k].image;
    if (!cv::imencode(".png", mat, png)) return core::Status::Error(path.string() + ": PNG failed");
    if (core::Status s = core::WriteFileAtomically(
            path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
        !s.ok()) {
      return s;
    }
  }
  if (core::Status s = calibration::WriteTagLayout(scene.layout, dir / "tag_layout.yaml");
      !s.ok()) {
    return s;
  }
  if (core::Status s = calibration::WriteMrcalCameraModel(dir / "camera.cameramodel", scene.camera);
      !s.ok()) {
    return s;
  }
  return calibration::WriteCameraMountYaml(scene.true_mount, dir / "true_extrinsics.yaml");
}

}  // namespace groundline::sim
