// The commissioning scene: the floor camera of a vehicle that drives slowly
// across a mat of AprilTags (tag36h11) laid flat on the floor at surveyed
// poses, for testing floor extrinsics calibration (calibration/floor_extrinsics.h).
//
// Rendering is FloorRenderer's forward model (floor_camera.h): every pixel's
// ray through the mrcal camera meets the floor; the tags are markings of the
// scene's World, each a white square (the tag's white outer ring and data
// background, total_width cells) with its black cells (runs of black cells
// along each pattern row) on top, from libapriltag's printed pattern
// (calibration::Tag36h11Pattern). Realism comes from the renderer's nuisances:
// box-filter anti-aliasing at edges (S x S samples), concrete texture and
// light gradient around the tags, motion blur at the creep speed, sensor noise.
//
// Frames: the floor frame is the map frame of the renderer; the tag layout is
// in it (frame: floor) with one surveyed vehicle pose per image.
#ifndef GROUNDLINE_SIM_COMMISSIONING_SCENE_H_
#define GROUNDLINE_SIM_COMMISSIONING_SCENE_H_

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/tag_layout.h"
#include "groundline/core/status.h"
#include "groundline/sim/floor_camera.h"
#include "groundline/sim/world.h"

namespace groundline::sim {

struct CommissioningOptions {
  // The camera and its TRUE mount (camera.mount): the defaults perturb the
  // reference mount by a few millimetres and tenths of a degree.
  FloorCameraOptions camera = DefaultCamera();
  FloorRenderOptions render = DefaultRender();

  // The tag mat: tag_rows x tag_cols tags, centres on a grid of pitch
  // tag_pitch_m starting at mat_origin_m (floor frame), ids from first_tag_id,
  // each turned by a seeded yaw in [-pi, pi) (the survey records it).
  int tag_rows = 6;          // along floor x
  int tag_cols = 5;          // along floor y
  double tag_size_m = 0.16;  // edge of the outer black square
  double tag_pitch_m = 0.36;
  Vector2 mat_origin_m = Vector2(0.7, -0.72);
  int first_tag_id = 0;

  // The drive: `poses` stops of base_link along floor x from start_x_m in
  // steps of step_x_m, each with a seeded lateral offset (+-lateral_jitter_m)
  // and yaw (+-yaw_jitter_rad); images are taken creeping at speed_mps.
  int poses = 6;
  double start_x_m = -0.3;
  double step_x_m = 0.25;
  double lateral_jitter_m = 0.08;
  double yaw_jitter_rad = 0.06;
  double speed_mps = 0.05;

  std::uint64_t seed = 1;

  core::Status Validate() const;
  static FloorCameraOptions DefaultCamera();
  static FloorRenderOptions DefaultRender();
  // A 480 x 384 camera (fx = 425 px, 3 x 3 anti-aliasing samples) looking more
  // steeply down at a mat of larger tags: the scene of the unit tests (fast to
  // render, also under sanitizers).
  static CommissioningOptions Small();
};

struct CommissioningScene {
  calibration::TagLayout layout;  // frame: floor, one vehicle pose per image
  calibration::CameraModel camera;
  calibration::CameraMount true_mount;
  World world;  // the floor with the tags as markings
};

// The layout, camera and world (no rendering).
core::Result<CommissioningScene> MakeCommissioningScene(const CommissioningOptions& options);

// The world whose markings are the tags of a floor-frame layout.
World TagMatWorld(const calibration::TagLayout& layout);

// Renders the image of every vehicle pose, in layout.vehicle_poses order.
core::Result<std::vector<GreyImage>> RenderCommissioningImages(const CommissioningScene& scene,
                                                               const CommissioningOptions& options);

// Writes into dir: images/<name>.png, tag_layout.yaml, camera.cameramodel and
// true_extrinsics.yaml (camera_mount_yaml.h). Creates dir if needed.
core::Status WriteCommissioningScene(const CommissioningScene& scene,
                                     const std::vector<GreyImage>& images,
                                     const std::filesystem::path& dir);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_COMMISSIONING_SCENE_H_
