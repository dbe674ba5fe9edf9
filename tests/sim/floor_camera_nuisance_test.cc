#include <gtest/gtest.h>

#include <cmath>

#include "groundline/sim/floor_camera.h"
#include "flat_world.h"

namespace groundline::sim {
namespace {

using ::groundline::testing::FlatWorld;

GreyImage RenderFlat(const FloorRenderOptions& options, std::uint64_t frame = 0,
                     const BaseVelocity& velocity = {}) {
  FloorCameraOptions camera;  // a quarter-resolution imager keeps the test fast
  camera.width_px = 320;
  camera.height_px = 256;
  camera.focal_px = 283.0;
  camera.principal_offset_px = {0.0, 0.0};
  const FloorRenderer renderer =
      *FloorRenderer::Create(FlatWorld(), *camera.MakeCameraModel(), camera.mount, options);
  return renderer.Render(core::SE2(1.3, 0.7, 0.2), velocity, frame);
}

double Mean(const GreyImage& image) {
  double s = 0;
  for (const std::uint8_t p : image.pixels) s += p;
  return s / static_cast<double>(image.pixels.size());
}

TEST(FloorCameraNuisances, IdealFlatFloorIsUniform) {
  const GreyImage image = RenderFlat(FloorRenderOptions::Ideal());
  for (const std::uint8_t p : image.pixels) ASSERT_EQ(p, 82);  // 255 * 0.32
}

// Sensor noise: the standard deviation over a flat floor is
// sqrt(read^2 + DN / electrons_per_dn), and it is seeded by the frame index.
TEST(FloorCameraNuisances, SensorNoiseHasTheConfiguredSpread) {
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  options.noise = true;
  options.read_noise_dn = 3.0;
  options.electrons_per_dn = 20.0;
  const GreyImage a = RenderFlat(options, 5);
  double s = 0, s2 = 0;
  for (const std::uint8_t p : a.pixels) {
    s += p;
    s2 += static_cast<double>(p) * p;
  }
  const double n = static_cast<double>(a.pixels.size());
  const double sd = std::sqrt(s2 / n - (s / n) * (s / n));
  const double expected = std::sqrt(9.0 + 81.6 / 20.0 + 1.0 / 12.0);  // + rounding
  EXPECT_NEAR(s / n, 81.6, 0.1);
  EXPECT_NEAR(sd, expected, 0.05 * expected);
  EXPECT_EQ(RenderFlat(options, 5).pixels, a.pixels);
  EXPECT_NE(RenderFlat(options, 6).pixels, a.pixels);
}

// Glare blobs on a dense luminaire grid: bright spots appear, and their count
// grows with the peak.
TEST(FloorCameraNuisances, GlareAddsBrightBlobs) {
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  options.glare = true;
  options.luminaire_spacing_x_m = 1.0;
  options.luminaire_spacing_y_m = 1.0;
  const auto bright_fraction = [](const GreyImage& image) {
    double n = 0;
    for (const std::uint8_t p : image.pixels) n += p > 82 + 40;
    return n / static_cast<double>(image.pixels.size());
  };
  const double f1 = bright_fraction(RenderFlat(options));
  options.glare_peak_dn = 170.0;
  const double f2 = bright_fraction(RenderFlat(options));
  EXPECT_GT(f1, 0.005);
  EXPECT_GT(f2, 1.3 * f1);
  EXPECT_EQ(bright_fraction(RenderFlat(FloorRenderOptions::Ideal())), 0.0);
}

// Texture, scuffs and oil vary the floor; lux scales it; shadows darken part of it.
TEST(FloorCameraNuisances, TextureLightAndShadowsChangeTheStatistics) {
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  options.texture = true;
  const GreyImage textured = RenderFlat(options);
  int lo = 255, hi = 0;
  for (const std::uint8_t p : textured.pixels) {
    lo = std::min<int>(lo, p);
    hi = std::max<int>(hi, p);
  }
  EXPECT_GT(hi - lo, 8);
  EXPECT_NEAR(Mean(textured), 81.6, 10.0);
  FloorRenderOptions dim = FloorRenderOptions::Ideal();
  dim.lux = 250.0;
  EXPECT_NEAR(Mean(RenderFlat(dim)), 41.0, 0.6);
  FloorRenderOptions shadowed = FloorRenderOptions::Ideal();
  shadowed.shadows = true;
  shadowed.shadow_cover = 1.0;
  shadowed.shadow_factor = 0.5;
  EXPECT_NEAR(Mean(RenderFlat(shadowed)), 40.8, 0.6);
}

// The default (all nuisances) render is a pure function of seed and frame.
TEST(FloorCameraNuisances, DeterministicForASeed) {
  FloorRenderOptions options;
  const GreyImage a = RenderFlat(options, 3, {1.5, 0.1});
  EXPECT_EQ(RenderFlat(options, 3, {1.5, 0.1}).pixels, a.pixels);
  options.seed = 2;
  EXPECT_NE(RenderFlat(options, 3, {1.5, 0.1}).pixels, a.pixels);
}

// Motion blur smears a transverse bar along the direction of travel: the bar's
// edge gets wider with speed.
TEST(FloorCameraNuisances, MotionBlurWidensEdgesWithSpeed) {
  World world = FlatWorld();
  FloorMarking bar;
  bar.kind = MarkingKind::kStopBar;
  bar.colour = MarkingColour::kWhite;
  bar.width_m = 0.1;
  bar.polyline_m = {{1.2, -1.0}, {1.2, 1.0}};
  world.markings.push_back(bar);
  FloorRenderOptions options = FloorRenderOptions::Ideal();
  options.motion_blur = true;
  options.exposure_s = 0.004;
  const FloorCameraOptions camera;
  const FloorRenderer renderer =
      *FloorRenderer::Create(world, *camera.MakeCameraModel(), camera.mount, options);
  // Count the column's partially covered (intermediate) pixels.
  const auto ramp = [&](double speed) {
    const GreyImage image = renderer.Render(core::SE2(), {speed, 0.0});
    int n = 0;
    for (int v = 0; v < 1024; ++v) {
      const int p = image.at(640, v);
      n += p > 90 && p < 195;
    }
    return n;
  };
  const int still = ramp(0.0);
  const int fast = ramp(2.0);
  EXPECT_LE(still, 4);
  EXPECT_GE(fast, still + 6);  // 8 mm of travel is several pixels at 1.2 m
}

}  // namespace
}  // namespace groundline::sim
