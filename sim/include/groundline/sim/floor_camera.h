// The simulated floor camera: 8-bit grey images of the floor seen by the
// downward-tilted camera of a vehicle at pose T_map_base.
//
// Rendering is a forward model through the calibrated camera, never through an
// inverse-perspective table (the perception module must not share this path):
// 1. Once per camera and mount (the camera is rigid on the vehicle), every pixel
//    centre is unprojected with calibration::CameraModel::UnprojectBatch (mrcal)
//    and its ray intersected with the floor z = 0 in base_link. The local
//    affine map d(floor)/d(pixel) is taken by central differences of those
//    floor points; it is exact to second order inside one pixel.
// 2. Each frame transforms the pixel floor points by T_map_base and shades them
//    with the floor's reflectance at that map point. Marking coverage is
//    anti-aliased by box-filter supersampling (S x S sub-pixel points through
//    the affine map) on the pixels whose footprint straddles a marking edge;
//    pixels wholly inside or outside every marking take one sample.
//    The floor's low-frequency fields (coarse texture octaves, scuff and oil
//    masks, illumination, shadows, glare; features >= ~10 cm) are evaluated on
//    every 8th pixel and interpolated bilinearly; thresholds that make hard
//    edges (shadow boundaries) are applied after the interpolation, so edges
//    stay sharp. Fine texture, scuff streaks and markings are per pixel.
// 3. Then illumination (lux -> exposure), glare, motion blur along the image
//    motion of the floor during the exposure (per pixel, the sharp image is
//    averaged along (d floor/d pixel)^-1 times the floor's displacement in
//    base_link over exposure_s), and sensor noise (read + shot, Gaussian).
//
// 4. Occluders (forklifts, pedestrians, other robots passing in front of the
//    camera; options.occlusion): solid boxes drawn over the floor by forward
//    projection. Each face turned towards the camera is cut into 16 x 16 quads
//    whose corners go through CameraModel::Project (so edges follow the lens
//    distortion), filled hard-edged with a flat shade (top 1, sides 0.6 of
//    the box's reflectance under options.lux), farthest box first. Drawn
//    after the motion blur, before the noise. Quads with a corner less than
//    2 cm in front of the camera or more than ~72 deg off its axis are
//    skipped (a box touching the lens).
//
// Not modelled: lens vignetting, rolling shutter (the sensor is global
// shutter), shadows cast by occluders, their own motion blur.
//
// Throughput (benchmarks/sim/floor_camera_benchmark.cc): about 3 frames/s on
// one core of the development machine with every default nuisance on; the
// pixel table costs ~2 s once per renderer.
//
// Reflectance of the floor (all procedural fields are fixed in the map frame and
// seeded, so they move with the floor): concrete with multi-octave value noise;
// markings as bands of width_m around their polylines (dashed tape cut along its
// arc length), grey from the colour's linear-sRGB luminance, worn in patches to
// concrete where a seeded field falls below the marking's wear_fraction
// quantile; joints are markings too (dark grooves). Nuisances: tire scuffs and
// oil stains (dark blobs) darken the concrete; scuffs are curved streaks of
// random orientation as turning tires leave them: arcs of 1-4 m radius,
// 0.8-3 m long, 2-4 cm wide with soft edges and tapered ends, in patches
// covering ~40 % of the floor, darkening ~7.5 % of a patch's area on average
// (by up to scuff_darkness); unlike joints and tape they follow no axis;
// illumination is a lux level with a smooth gradient and optional hard-edged
// shadow patches; glare blobs are isotropic bright spots on a jittered
// luminaire grid; sensor noise is Gaussian read noise plus shot noise.
//
// Pixel value (before glare, blur and noise):
//   DN = 255 * reflectance * lux_local / exposure_reference_lux, clamped.
// Pixels whose ray misses the floor (above the horizon) or meets it beyond
// max_floor_range_m show the flat wall tone wall_dn.
//
// Thread-safety: a FloorRenderer is immutable after Create; Render is const and
// may run concurrently on several threads.
#ifndef GROUNDLINE_SIM_FLOOR_CAMERA_H_
#define GROUNDLINE_SIM_FLOOR_CAMERA_H_

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/sim/world.h"

namespace groundline::sim {

// The camera itself: intrinsics (LENSMODEL_OPENCV5) and mount. The defaults are
// the reference AGV: 6 mm lens on 5.3 um pixels (fx = fy = 6 / 0.0053 = 1132 px),
// principal point near the centre of the 1280x1024 imager, mild barrel
// distortion, mounted per calibration::CameraMount's defaults.
struct FloorCameraOptions {
  int width_px = 1280;
  int height_px = 1024;
  double focal_px = 1132.0;
  // Principal point = image centre ((w - 1) / 2, (h - 1) / 2) + this offset.
  std::array<double, 2> principal_offset_px = {3.5, -2.5};
  // OpenCV k1 k2 p1 p2 k3.
  std::array<double, 5> distortion = {-0.05, 0.012, 2.0e-4, -1.5e-4, 0.0};
  calibration::CameraMount mount;
  double sensor_rate_hz = 60.0;

  core::Status Validate() const;
  // The mrcal camera of these options (options must be valid).
  core::Result<calibration::CameraModel> MakeCameraModel() const;
};

// Each nuisance has an on/off switch and an intensity.
struct FloorRenderOptions {
  int supersampling = 3;  // S: S x S sub-pixel samples at marking edges, 1..8
  double max_floor_range_m = 30.0;
  double wall_dn = 35.0;  // flat tone of rows above the horizon
  double concrete_reflectance = 0.32;
  double tape_reflectance_scale = 0.85;  // tape reflects this fraction of its colour

  bool texture = true;
  double texture_contrast = 0.25;  // relative reflectance variation, peak to peak ~2x this
  bool wear = true;                // use each marking's wear_fraction
  bool scuffs = true;
  double scuff_darkness = 0.15;  // fraction of reflectance removed at a full scuff
  bool oil = true;
  double oil_darkness = 0.4;

  double lux = 500.0;                     // mean illuminance on the floor
  double exposure_reference_lux = 500.0;  // lux at which reflectance 1 gives 255
  bool illumination_gradient = true;
  double gradient_fraction = 0.25;  // +-this relative lux variation over ~10 m
  bool shadows = false;
  double shadow_factor = 0.4;  // lux multiplier in shadow
  double shadow_cover = 0.3;   // fraction of the floor in shadow (approximate)

  bool glare = true;
  double glare_peak_dn = 110.0;  // added at a blob's centre
  double glare_sigma_m = 0.12;   // Gaussian radius of a blob
  double luminaire_spacing_x_m = 6.0;
  double luminaire_spacing_y_m = 4.0;
  // Strip luminaires: with a pitch > 0 each luminaire of the grid is a row of
  // spots along the map's x axis, glare_row_pitch_m apart over
  // glare_row_length_m (the reflections of an LED strip line up).
  double glare_row_pitch_m = 0.0;
  double glare_row_length_m = 3.0;

  // The straight nuisances (floor_nuisances.h lists their geometry); all off
  // by default. Cast shadows: straight-edged shadows of racks and pallets,
  // fixed on the floor (rectangles 0.8-10 m long, 0.3-1.5 m wide, 70 % along a
  // map axis), light multiplied by cast_shadow_factor inside, a soft edge of
  // shadow_penumbra_m.
  bool cast_shadows = false;
  double cast_shadow_factor = 0.5;
  double cast_shadow_cover = 0.15;  // fraction of the floor (expected)
  double shadow_penumbra_m = 0.01;
  // The vehicle's own shadow: its top face (a box around base_link) projected
  // onto the floor from the nearest luminaire of the grid, luminaire_height_m
  // high; light multiplied by vehicle_shadow_factor inside. It moves with the
  // vehicle and changes shape as the luminaire passes.
  bool vehicle_shadow = false;
  double vehicle_shadow_factor = 0.6;
  double luminaire_height_m = 8.0;
  double vehicle_front_m = 0.85, vehicle_back_m = -0.85, vehicle_half_width_m = 0.46;
  double vehicle_height_m = 1.2;
  // Tire marks: dark streaks along the lanes (85 % within 2 deg of a map
  // axis), in pairs 0.5-0.7 m apart, 3-20 m long, 4-10 cm wide with soft
  // edges, their strength varying along them; tire_mark_density pairs per
  // 100 m^2, darkening up to tire_mark_darkness.
  bool tire_marks = false;
  double tire_mark_darkness = 0.15;
  double tire_mark_density = 1.0;
  // Patches of repaired concrete: rectangles 0.5-3 m a side (80 % along the
  // map axes) whose reflectance differs by a factor 1 +- (0.3-1) x
  // patch_contrast, with sharp straight seams; patch_cover of the floor.
  bool patches = false;
  double patch_contrast = 0.15;
  double patch_cover = 0.08;
  // Wet areas: smooth-edged blobs (~2-4 m) darker by wet_darkness, where the
  // glare is (1 + wet_glare_gain) times stronger; wet_cover of the floor.
  bool wet = false;
  double wet_darkness = 0.3;
  double wet_glare_gain = 1.0;
  double wet_cover = 0.1;

  bool motion_blur = true;
  double exposure_s = 0.004;

  bool occlusion = true;  // draw the occluders passed to Render

  // Things standing on the floor (floor_nuisances.h), drawn as occluders (so
  // only with occlusion): the world's static obstacles (racks, pallets,
  // columns, walls, doors) where the camera sees them, and, with
  // clutter_per_100m > 0, boxes, pallets and posts placed beside the
  // vehicle's route, that many per 100 m of it, never in its way nor on a
  // marking. Their vertical edges smear along rays from the camera in the
  // bird's-eye view. Off by default.
  bool standing_objects = false;
  double clutter_per_100m = 0.0;

  bool noise = true;
  double read_noise_dn = 1.5;
  double electrons_per_dn = 40.0;  // shot noise: variance DN / electrons_per_dn

  std::uint64_t seed = 1;

  core::Status Validate() const;
  // Everything off: sharp noise-free reflectance under flat light.
  static FloorRenderOptions Ideal();
};

struct GreyImage {
  int width_px = 0;
  int height_px = 0;
  std::vector<std::uint8_t> pixels;  // row-major, width_px * height_px
  std::uint8_t at(int u, int v) const { return pixels[static_cast<std::size_t>(v) * width_px + u]; }
};

// A solid object in front of the floor: its footprint in the map frame,
// extruded from z_min_m to z_max_m above the floor, with a diffuse reflectance
// that varies by up to +-texture (relative) in patches of ~0.2 m on its faces.
struct Occluder {
  OrientedBox footprint_m;
  double z_min_m = 0.0;
  double z_max_m = 2.0;
  double reflectance = 0.12;
  double texture = 0.0;
};

// The occluders of the world's moving obstacles at a stamp (circles become
// squares of their radius).
std::vector<Occluder> OccludersAt(const World& world, double stamp_s);

// The vehicle's velocity in base_link during the exposure (motion blur).
struct BaseVelocity {
  double forward_mps = 0.0;
  double yaw_rate_radps = 0.0;
};

class FloorRenderer {
 public:
  // Fails when the options are invalid or no pixel sees the floor.
  static core::Result<FloorRenderer> Create(const World& world,
                                            const calibration::CameraModel& camera,
                                            const calibration::CameraMount& mount,
                                            const FloorRenderOptions& options);

  // The image at T_map_base. frame_index seeds the sensor noise (the floor's
  // fields depend on options.seed alone). Occluders are drawn when
  // options.occlusion is set.
  GreyImage Render(const core::SE2& T_map_base, const BaseVelocity& velocity = {},
                   std::uint64_t frame_index = 0,
                   const std::vector<Occluder>& occluders = {}) const;

  const calibration::CameraModel& camera() const;
  const calibration::CameraMount& mount() const;
  // Fraction of pixels that see the floor within max_floor_range_m.
  double FloorPixelFraction() const;

  struct Impl;

 private:
  explicit FloorRenderer(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<const Impl> impl_;
};

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_FLOOR_CAMERA_H_
