// The straight nuisances of the floor renderer (floor_nuisances.h): each one
// alone draws what its geometry says, where FloorNuisanceSegments says.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "flat_world.h"
#include "floor_camera_internal.h"
#include "groundline/core/random_draws.h"
#include "groundline/sim/floor_nuisances.h"

namespace groundline::sim {
namespace {

using internal::CoarseFields;
using internal::FloorFields;

std::vector<NuisanceSegment> SegmentsNearOrigin(const FloorRenderOptions& o) {
  return FloorNuisanceSegments(o, Vector2(-30, -30), Vector2(30, 30));
}

// Unit normal to the left of a -> b (the inside of a counter-clockwise rectangle).
Vector2 LeftNormal(const NuisanceSegment& s) {
  const Vector2 d = (s.b_m - s.a_m).normalized();
  return Vector2(-d.y(), d.x());
}

TEST(FloorStraightNuisances, CastShadowEdgesAreStraightLightSteps) {
  FloorRenderOptions o = FloorRenderOptions::Ideal();
  o.cast_shadows = true;
  o.cast_shadow_factor = 0.5;
  o.cast_shadow_cover = 0.15;
  o.shadow_penumbra_m = 0.005;
  const FloorFields fields(o);
  const std::vector<NuisanceSegment> edges = SegmentsNearOrigin(o);
  ASSERT_GT(edges.size(), 40u);
  int steps = 0, checked = 0;
  for (const NuisanceSegment& e : edges) {
    ASSERT_EQ(e.cls, NuisanceClass::kCastShadowEdge);
    const Vector2 mid = 0.5 * (e.a_m + e.b_m), n = LeftNormal(e);
    const float inside = fields.Light(mid + 0.02 * n, CoarseFields{});
    const float outside = fields.Light(mid - 0.02 * n, CoarseFields{});
    // The inside is always in shadow; the outside is lit unless another
    // shadow covers it.
    EXPECT_NEAR(inside, 0.5f, 1e-4f);
    ++checked;
    if (std::abs(outside - 1.0f) < 1e-4f) ++steps;
  }
  EXPECT_GT(steps, 0.8 * checked);
  // Overlapping rectangles of expected cover c shade 1 - exp(-c) of the floor.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-200.0, 200.0);
  int shaded = 0;
  constexpr int kSamples = 40000;
  for (int i = 0; i < kSamples; ++i) {
    shaded += fields.Light(core::DrawVector<2>(u, rng), CoarseFields{}) < 0.75f;
  }
  EXPECT_NEAR(static_cast<double>(shaded) / kSamples, 1.0 - std::exp(-0.15), 0.03);
}

TEST(FloorStraightNuisances, GlareRowsAreSpotsInALineAlongX) {
  FloorRenderOptions o = FloorRenderOptions::Ideal();
  o.glare = true;
  o.glare_peak_dn = 100.0;
  o.glare_sigma_m = 0.05;
  o.glare_row_pitch_m = 0.25;
  o.glare_row_length_m = 3.0;
  const FloorFields fields(o);
  const std::vector<NuisanceSegment> rows = SegmentsNearOrigin(o);
  ASSERT_GT(rows.size(), 20u);
  for (const NuisanceSegment& r : rows) {
    ASSERT_EQ(r.cls, NuisanceClass::kGlareRow);
    EXPECT_NEAR(r.a_m.y(), r.b_m.y(), 1e-12);  // along x
    EXPECT_NEAR((r.b_m - r.a_m).norm(), 3.0, 1e-9);
    const Vector2 mid = 0.5 * (r.a_m + r.b_m);
    // On a spot, between two spots, beside the row and beyond its end.
    EXPECT_NEAR(fields.Coarse(mid).glare, 100.0f, 1.0f);
    EXPECT_LT(fields.Coarse(mid + Vector2(0.125, 0.0)).glare, 10.0f);
    EXPECT_LT(fields.Coarse(mid + Vector2(0.0, 0.3)).glare, 1.0f);
    EXPECT_LT(fields.Coarse(r.b_m + Vector2(0.3, 0.0)).glare, 1.0f);
  }
  // Without a pitch the luminaires are single spots: no rows.
  o.glare_row_pitch_m = 0.0;
  EXPECT_TRUE(SegmentsNearOrigin(o).empty());
}

TEST(FloorStraightNuisances, TireMarksComeInPairsAlongTheLanes) {
  FloorRenderOptions o = FloorRenderOptions::Ideal();
  o.tire_marks = true;
  o.tire_mark_darkness = 0.2;
  o.tire_mark_density = 2.0;
  const FloorFields fields(o);
  const std::vector<NuisanceSegment> marks = SegmentsNearOrigin(o);
  ASSERT_GT(marks.size(), 20u);
  int along_axis = 0, darker = 0;
  for (const NuisanceSegment& m : marks) {
    ASSERT_EQ(m.cls, NuisanceClass::kTireMark);
    const Vector2 d = (m.b_m - m.a_m).normalized();
    const double off_axis = std::min(std::abs(d.x()), std::abs(d.y()));
    if (off_axis < std::sin(2.0 * M_PI / 180.0) + 1e-9) ++along_axis;
    const double length = (m.b_m - m.a_m).norm();
    EXPECT_GE(length, 0.8 * 3.0 - 1e-9);
    EXPECT_LE(length, 20.0 + 1e-9);
    const Vector2 mid = 0.5 * (m.a_m + m.b_m);
    const float on = fields.Concrete(mid, CoarseFields{});
    const float beside = fields.Concrete(mid + 0.3 * LeftNormal(m), CoarseFields{});
    if (on < 0.99f * beside) ++darker;
    EXPECT_GE(on,
              static_cast<float>(o.concrete_reflectance * (1.0 - o.tire_mark_darkness)) - 1e-6f);
  }
  EXPECT_GT(along_axis, 0.7 * static_cast<double>(marks.size()));
  EXPECT_GT(darker, 0.9 * static_cast<double>(marks.size()));
}

TEST(FloorStraightNuisances, PatchSeamsAreSharpReflectanceSteps) {
  FloorRenderOptions o = FloorRenderOptions::Ideal();
  o.patches = true;
  o.patch_contrast = 0.2;
  o.patch_cover = 0.1;
  const FloorFields fields(o);
  const std::vector<NuisanceSegment> seams = SegmentsNearOrigin(o);
  ASSERT_GT(seams.size(), 40u);
  int steps = 0;
  for (const NuisanceSegment& s : seams) {
    ASSERT_EQ(s.cls, NuisanceClass::kPatchSeam);
    const Vector2 mid = 0.5 * (s.a_m + s.b_m), n = LeftNormal(s);
    const double ratio = fields.Concrete(mid + 0.005 * n, CoarseFields{}) /
                         fields.Concrete(mid - 0.005 * n, CoarseFields{});
    // One patch alone: a factor 1 +- (0.3-1) x contrast across 1 cm.
    if (std::abs(ratio - 1.0) >= 0.3 * 0.2 - 1e-4 && std::abs(ratio - 1.0) <= 0.2 + 1e-4) ++steps;
  }
  EXPECT_GT(steps, 0.8 * static_cast<double>(seams.size()));
}

TEST(FloorStraightNuisances, VehicleShadowIsCastFromTheNearestLuminaire) {
  FloorRenderOptions o = FloorRenderOptions::Ideal();
  o.vehicle_shadow = true;
  o.vehicle_shadow_factor = 0.5;
  o.luminaire_height_m = 8.0;
  o.vehicle_height_m = 1.2;
  o.vehicle_front_m = 0.45;
  const std::uint32_t seed = internal::FieldSeed(o);
  const Vector2 light = internal::LuminaireAt(o, seed, 3, 2);
  const double scale = 8.0 / (8.0 - 1.2);
  const auto front = [](const std::vector<Vector2>& polygon) {
    double x = -1e9;
    for (const Vector2& p : polygon) x = std::max(x, p.x());
    return x;
  };
  // Under the luminaire: the top face scaled about the light.
  const std::optional<std::vector<Vector2>> under =
      VehicleShadowPolygon(o, core::SE2(light.x(), light.y(), 0.0));
  ASSERT_TRUE(under.has_value());
  EXPECT_NEAR(front(*under), 0.45 * scale, 1e-9);
  // 1.5 m past it (facing +x): the shadow reaches further ahead.
  const core::SE2 past(light.x() + 1.5, light.y(), 0.0);
  const std::optional<std::vector<Vector2>> ahead = VehicleShadowPolygon(o, past);
  ASSERT_TRUE(ahead.has_value());
  EXPECT_NEAR(front(*ahead), -1.5 + (0.45 + 1.5) * scale, 1e-9);

  // Rendered: the near floor (the bottom rows) is in the shadow, the far floor
  // (the top rows) is not; with factor 0.5 the shadow halves the light.
  FloorCameraOptions camera;
  camera.width_px = 320;
  camera.height_px = 256;
  camera.focal_px = 283.0;
  camera.principal_offset_px = {0.0, 0.0};
  const FloorRenderer renderer = *FloorRenderer::Create(::groundline::testing::FlatWorld(),
                                                        *camera.MakeCameraModel(), camera.mount, o);
  const GreyImage image = renderer.Render(past);
  EXPECT_NEAR(image.at(160, 250), 41, 1);  // ~0.6 m ahead: 255 * 0.32 * 0.5
  EXPECT_NEAR(image.at(160, 5), 82, 1);    // ~2.3 m ahead: lit
  o.vehicle_shadow = false;
  EXPECT_FALSE(VehicleShadowPolygon(o, past).has_value());
}

TEST(FloorStraightNuisances, RandomizedScenesAreValidAndVaried) {
  int rows = 0, vehicle = 0, wet = 0;
  double lux_min = 1e9, lux_max = 0.0;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    const FloorRenderOptions o = RandomizedRenderOptions(seed);
    ASSERT_TRUE(o.Validate().ok()) << "seed " << seed << ": " << o.Validate().message();
    EXPECT_TRUE(o.cast_shadows && o.tire_marks && o.patches && o.texture && o.glare);
    rows += o.glare_row_pitch_m > 0.0;
    vehicle += o.vehicle_shadow;
    wet += o.wet;
    lux_min = std::min(lux_min, o.lux);
    lux_max = std::max(lux_max, o.lux);
    EXPECT_EQ(RandomizedRenderOptions(seed).lux, o.lux);  // seeded
  }
  // Each optional nuisance in some scenes and not in others.
  for (const int n : {rows, vehicle, wet}) {
    EXPECT_GT(n, 10);
    EXPECT_LT(n, 50);
  }
  EXPECT_LT(lux_min, 400.0);
  EXPECT_GT(lux_max, 1000.0);
}

// The renderer's shortcuts give the exact functions' answers: the capped
// stroke distance is exact up to its cap and above the cap beyond it, and the
// soft rectangle edge equals SoftInside of the signed distance, at points
// drawn densely around a stroke's and a rectangle's corners and sides.
TEST(FloorStraightNuisances, DistanceShortcutsAgreeWithTheExactFunctions) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> coord(-0.6, 1.6), cap(-0.05, 0.05);
  internal::Stroke stroke;
  stroke.a_m = Vector2(0.1, 0.2);
  stroke.dir = Vector2(std::cos(0.3), std::sin(0.3));
  stroke.length_m = 1.0;
  stroke.half_width_m = 0.025;
  int capped = 0;
  for (int k = 0; k < 200000; ++k) {
    const Vector2 p = core::DrawVector<2>(coord, rng);
    const double c = cap(rng);
    const double exact = internal::StrokeSignedDistance(stroke, p);
    const double fast = internal::StrokeSignedDistanceCapped(stroke, p, c);
    if (exact <= c) {
      ASSERT_EQ(fast, exact) << p.transpose() << " cap " << c;
    } else {
      ASSERT_GT(fast, c) << p.transpose() << " cap " << c;
      ++capped;
    }
  }
  EXPECT_GT(capped, 1000);
  std::uniform_real_distribution<double> local(-0.3, 0.3);
  for (int k = 0; k < 200000; ++k) {
    const double along = local(rng), across = local(rng);
    for (const double penumbra : {0.001, 0.01, 0.2}) {
      ASSERT_EQ(
          internal::SoftInsideRect(along, across, 0.2, 0.1, penumbra),
          internal::SoftInside(internal::RectSignedDistance(along, across, 0.2, 0.1), penumbra))
          << along << " " << across << " " << penumbra;
    }
  }
}

}  // namespace
}  // namespace groundline::sim
