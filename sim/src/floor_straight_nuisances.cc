// The straight nuisances of the floor (cast shadows, the vehicle's shadow,
// glare rows, tire marks, patches), their geometry for evaluation, and the
// randomized nuisance preset (floor_nuisances.h).
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "floor_camera_internal.h"
#include "groundline/sim/floor_nuisances.h"

namespace groundline::sim {
namespace internal {
namespace {

constexpr std::uint32_t kGlare = 19, kCastShadows = 31, kTireMarks = 32, kPatches = 33;
constexpr double kTileMarginM = 0.06;

// Uniform draws for rectangle `index` of a field: the draw-th value in [lo, hi).
class RectDraws {
 public:
  RectDraws(std::uint32_t seed, std::int64_t index) : seed_(seed), index_(index) {}
  double Uniform(double lo, double hi) {
    return lo + (hi - lo) * HashU32(index_, draw_++, seed_) / 4294967296.0;
  }
  // A point uniform on the tile, y drawn first (core::DrawVector's order).
  Vector2 Centre() {
    const double y = Uniform(0.0, RectTile::kPeriodM);
    return Vector2(Uniform(0.0, RectTile::kPeriodM), y);
  }
  // A direction: with probability p_axis along a map axis (x or y) within
  // +-jitter_rad, otherwise uniform.
  Vector2 Direction(double p_axis, double jitter_rad) {
    const bool axis = Uniform(0.0, 1.0) < p_axis;
    const double base = Uniform(0.0, 1.0) < 0.5 ? 0.0 : 0.5 * std::numbers::pi;
    const double jitter = Uniform(-jitter_rad, jitter_rad);
    const double uniform = Uniform(0.0, std::numbers::pi);
    const double angle = axis ? base + jitter : uniform;
    return Vector2(std::cos(angle), std::sin(angle));
  }

 private:
  std::uint32_t seed_;
  std::int64_t index_;
  int draw_ = 0;
};

std::int64_t RectCount(double cover_or_density, double mean_area_m2) {
  return static_cast<std::int64_t>(
      std::lround(cover_or_density * RectTile::kPeriodM * RectTile::kPeriodM / mean_area_m2));
}

// The rectangle's corners, counter-clockwise.
std::array<Vector2, 4> Corners(const TileRect& r) {
  const Vector2 along = r.half_length_m * r.dir;
  const Vector2 left = r.half_width_m * Vector2(-r.dir.y(), r.dir.x());
  return {r.centre_m - along - left, r.centre_m + along - left, r.centre_m + along + left,
          r.centre_m - along + left};
}

}  // namespace

RectTile::RectTile(std::vector<TileRect> rects, double margin_m) : rects_(std::move(rects)) {
  cells_.assign(static_cast<std::size_t>(kCells) * kCells, {});
  for (std::size_t a = 0; a < rects_.size(); ++a) {
    Vector2 lo = Vector2::Constant(1e300), hi = Vector2::Constant(-1e300);
    for (const Vector2& c : Corners(rects_[a])) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
    const auto x0 = static_cast<std::int64_t>(std::floor((lo.x() - margin_m) / kCellM));
    const auto x1 = static_cast<std::int64_t>(std::floor((hi.x() + margin_m) / kCellM));
    const auto y0 = static_cast<std::int64_t>(std::floor((lo.y() - margin_m) / kCellM));
    const auto y1 = static_cast<std::int64_t>(std::floor((hi.y() + margin_m) / kCellM));
    // A rectangle is at most 10 m: one tile copy either way is enough.
    RegisterOnTile(static_cast<std::uint32_t>(a), x0, x1, y0, y1, kCells, &cells_);
  }
}

RectTile MakeCastShadows(const FloorRenderOptions& o, std::uint32_t seed) {
  if (!o.cast_shadows) return {};
  constexpr double kMeanAreaM2 = 0.5 * (0.8 + 10.0) * 0.5 * (0.3 + 1.5);
  std::vector<TileRect> rects;
  const std::int64_t n = RectCount(o.cast_shadow_cover, kMeanAreaM2);
  for (std::int64_t i = 0; i < n; ++i) {
    RectDraws d(seed + kCastShadows, i);
    TileRect r;
    r.centre_m = d.Centre();
    r.dir = d.Direction(0.7, 0.0);
    r.half_length_m = 0.5 * d.Uniform(0.8, 10.0);
    r.half_width_m = 0.5 * d.Uniform(0.3, 1.5);
    rects.push_back(r);
  }
  return RectTile(std::move(rects), o.shadow_penumbra_m + kTileMarginM);
}

RectTile MakeTireMarks(const FloorRenderOptions& o, std::uint32_t seed) {
  if (!o.tire_marks) return {};
  std::vector<TileRect> rects;
  const std::int64_t pairs = RectCount(o.tire_mark_density / 100.0, 1.0);
  for (std::int64_t i = 0; i < pairs; ++i) {
    RectDraws d(seed + kTireMarks, i);
    const Vector2 centre = d.Centre();
    const Vector2 dir = d.Direction(0.85, 2.0 * std::numbers::pi / 180.0);
    const double half_length = 0.5 * d.Uniform(3.0, 20.0);
    const double half_width = 0.5 * d.Uniform(0.04, 0.10);
    const double track = d.Uniform(0.5, 0.7);
    for (const double side : {-0.5, 0.5}) {
      TileRect r;
      r.centre_m = centre + side * track * Vector2(-dir.y(), dir.x());
      r.dir = dir;
      r.half_length_m = half_length * d.Uniform(0.8, 1.0);
      r.half_width_m = half_width;
      r.value = static_cast<float>(d.Uniform(0.5, 1.0));
      r.value2 = static_cast<float>(HashU32(i, side > 0 ? 1 : 0, seed + kTireMarks + 1) >> 8);
      rects.push_back(r);
    }
  }
  return RectTile(std::move(rects), kTileMarginM);
}

RectTile MakePatches(const FloorRenderOptions& o, std::uint32_t seed) {
  if (!o.patches) return {};
  constexpr double kMeanAreaM2 = 1.75 * 1.75;
  std::vector<TileRect> rects;
  const std::int64_t n = RectCount(o.patch_cover, kMeanAreaM2);
  for (std::int64_t i = 0; i < n; ++i) {
    RectDraws d(seed + kPatches, i);
    TileRect r;
    r.centre_m = d.Centre();
    r.dir = d.Direction(0.8, 0.0);
    r.half_length_m = 0.5 * d.Uniform(0.5, 3.0);
    r.half_width_m = 0.5 * d.Uniform(0.5, 3.0);
    const double sign = d.Uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
    r.value = static_cast<float>(1.0 + sign * d.Uniform(0.3, 1.0) * o.patch_contrast);
    rects.push_back(r);
  }
  return RectTile(std::move(rects), kTileMarginM);
}

Vector2 LuminaireAt(const FloorRenderOptions& o, std::uint32_t seed, std::int64_t ix,
                    std::int64_t iy) {
  const std::uint32_t h = HashU32(ix, iy, seed + kGlare);
  const double jx = 0.2 + 0.6 * (h & 0xffff) / 65535.0;
  const double jy = 0.2 + 0.6 * (h >> 16) / 65535.0;
  return Vector2((static_cast<double>(ix) + jx) * o.luminaire_spacing_x_m,
                 (static_cast<double>(iy) + jy) * o.luminaire_spacing_y_m);
}

float VehicleShadowLight(const std::vector<Vector2>& polygon, const Vector2& q_m, double factor,
                         double penumbra_m) {
  // Signed distance to a convex counter-clockwise polygon: the largest of the
  // distances to its edges' lines (exact inside and beside the edges).
  double sd = -1e300;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Vector2& a = polygon[k];
    const Vector2& b = polygon[(k + 1) % polygon.size()];
    const Vector2 e = (b - a).normalized();
    const Vector2 d = q_m - a;
    sd = std::max(sd, e.y() * d.x() - e.x() * d.y());  // > 0 right of a -> b: outside
  }
  return 1.0f - (1.0f - static_cast<float>(factor)) * SoftInside(sd, penumbra_m);
}

}  // namespace internal

std::string_view NuisanceClassName(NuisanceClass c) {
  switch (c) {
    case NuisanceClass::kCastShadowEdge:
      return "cast_shadow_edge";
    case NuisanceClass::kVehicleShadowEdge:
      return "vehicle_shadow_edge";
    case NuisanceClass::kGlareRow:
      return "glare_row";
    case NuisanceClass::kTireMark:
      return "tire_mark";
    case NuisanceClass::kPatchSeam:
      return "patch_seam";
    case NuisanceClass::kStandingObject:
      return "standing_object";
  }
  return "unknown";
}

namespace {

bool SegmentTouchesBox(const Vector2& a, const Vector2& b, const Vector2& lo, const Vector2& hi) {
  // Conservative: the segment's bounding box meets the box.
  return std::max(a.x(), b.x()) >= lo.x() && std::min(a.x(), b.x()) <= hi.x() &&
         std::max(a.y(), b.y()) >= lo.y() && std::min(a.y(), b.y()) <= hi.y();
}

// Every copy of the tile's rectangles that may meet [lo, hi]: fn(rect moved).
template <typename Fn>
void ForEachCopy(const internal::RectTile& tile, const Vector2& lo, const Vector2& hi, Fn&& fn) {
  const double p = internal::RectTile::kPeriodM;
  const auto k0x = static_cast<std::int64_t>(std::floor(lo.x() / p)) - 1;
  const auto k1x = static_cast<std::int64_t>(std::floor(hi.x() / p)) + 1;
  const auto k0y = static_cast<std::int64_t>(std::floor(lo.y() / p)) - 1;
  const auto k1y = static_cast<std::int64_t>(std::floor(hi.y() / p)) + 1;
  for (const internal::TileRect& r : tile.rects()) {
    for (std::int64_t ky = k0y; ky <= k1y; ++ky) {
      for (std::int64_t kx = k0x; kx <= k1x; ++kx) {
        internal::TileRect moved = r;
        moved.centre_m += p * Vector2(static_cast<double>(kx), static_cast<double>(ky));
        const double reach = moved.half_length_m + moved.half_width_m;
        if (!SegmentTouchesBox(moved.centre_m - Vector2::Constant(reach),
                               moved.centre_m + Vector2::Constant(reach), lo, hi)) {
          continue;
        }
        fn(moved);
      }
    }
  }
}

void AddEdges(NuisanceClass cls, const internal::TileRect& r, const Vector2& lo, const Vector2& hi,
              std::vector<NuisanceSegment>* out) {
  const std::array<Vector2, 4> c = internal::Corners(r);
  for (int k = 0; k < 4; ++k) {
    const Vector2& a = c[static_cast<std::size_t>(k)];
    const Vector2& b = c[static_cast<std::size_t>((k + 1) % 4)];
    if (SegmentTouchesBox(a, b, lo, hi)) out->push_back({cls, a, b});
  }
}

}  // namespace

std::vector<NuisanceSegment> FloorNuisanceSegments(const FloorRenderOptions& o, const Vector2& lo,
                                                   const Vector2& hi) {
  std::vector<NuisanceSegment> out;
  const std::uint32_t seed = internal::FieldSeed(o);
  ForEachCopy(internal::MakeCastShadows(o, seed), lo, hi, [&](const internal::TileRect& r) {
    AddEdges(NuisanceClass::kCastShadowEdge, r, lo, hi, &out);
  });
  ForEachCopy(internal::MakePatches(o, seed), lo, hi, [&](const internal::TileRect& r) {
    AddEdges(NuisanceClass::kPatchSeam, r, lo, hi, &out);
  });
  ForEachCopy(internal::MakeTireMarks(o, seed), lo, hi, [&](const internal::TileRect& r) {
    const Vector2 a = r.centre_m - r.half_length_m * r.dir,
                  b = r.centre_m + r.half_length_m * r.dir;
    if (SegmentTouchesBox(a, b, lo, hi)) out.push_back({NuisanceClass::kTireMark, a, b});
  });
  if (o.glare && o.glare_row_pitch_m > 0.0) {
    const double sx = o.luminaire_spacing_x_m, sy = o.luminaire_spacing_y_m;
    const int n = static_cast<int>(0.5 * o.glare_row_length_m / o.glare_row_pitch_m);
    for (auto iy = static_cast<std::int64_t>(std::floor(lo.y() / sy)) - 1;
         iy <= static_cast<std::int64_t>(std::floor(hi.y() / sy)) + 1; ++iy) {
      for (auto ix = static_cast<std::int64_t>(std::floor(lo.x() / sx)) - 1;
           ix <= static_cast<std::int64_t>(std::floor(hi.x() / sx)) + 1; ++ix) {
        const Vector2 lum = internal::LuminaireAt(o, seed, ix, iy);
        const Vector2 half(n * o.glare_row_pitch_m, 0.0);
        if (n > 0 && SegmentTouchesBox(lum - half, lum + half, lo, hi)) {
          out.push_back({NuisanceClass::kGlareRow, lum - half, lum + half});
        }
      }
    }
  }
  return out;
}

std::optional<std::vector<Vector2>> VehicleShadowPolygon(const FloorRenderOptions& o,
                                                         const core::SE2& T_map_base) {
  if (!o.vehicle_shadow || o.luminaire_height_m <= o.vehicle_height_m) return std::nullopt;
  const std::uint32_t seed = internal::FieldSeed(o);
  const Vector2 origin = T_map_base.translation();
  const auto cx = static_cast<std::int64_t>(std::floor(origin.x() / o.luminaire_spacing_x_m));
  const auto cy = static_cast<std::int64_t>(std::floor(origin.y() / o.luminaire_spacing_y_m));
  Vector2 light = internal::LuminaireAt(o, seed, cx, cy);
  for (std::int64_t dy = -1; dy <= 1; ++dy) {
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      const Vector2 l = internal::LuminaireAt(o, seed, cx + dx, cy + dy);
      if ((l - origin).squaredNorm() < (light - origin).squaredNorm()) light = l;
    }
  }
  // The light in base_link; the top face's corners projected from it onto the
  // floor, with the footprint: the box's shadow is their convex hull.
  const Vector2 l = T_map_base.Inverse() * light;
  const double scale = o.luminaire_height_m / (o.luminaire_height_m - o.vehicle_height_m);
  std::vector<Vector2> points;
  for (const double x : {o.vehicle_back_m, o.vehicle_front_m}) {
    for (const double y : {-o.vehicle_half_width_m, o.vehicle_half_width_m}) {
      points.push_back(l + scale * (Vector2(x, y) - l));
      points.emplace_back(x, y);
    }
  }
  // OpenCV's hull takes float points: it picks the vertices, which keep
  // their double coordinates.
  std::vector<cv::Point2f> points_f;
  for (const Vector2& p : points) {
    points_f.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  }
  std::vector<int> hull;
  cv::convexHull(points_f, hull, /*clockwise=*/false, /*returnPoints=*/false);
  std::vector<Vector2> polygon;
  for (const int k : hull) polygon.push_back(points[static_cast<std::size_t>(k)]);
  // OpenCV's "counter-clockwise" is in image axes (y down); make it
  // counter-clockwise in base_link (y left).
  double area = 0.0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Vector2& a = polygon[k];
    const Vector2& b = polygon[(k + 1) % polygon.size()];
    area += a.x() * b.y() - a.y() * b.x();
  }
  if (area < 0.0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

FloorRenderOptions RandomizedRenderOptions(std::uint64_t seed) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + 0x5EED);
  const auto u = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const auto chance = [&](double p) { return u(0.0, 1.0) < p; };
  FloorRenderOptions o;
  o.seed = seed;
  o.texture = true;
  o.texture_contrast = u(0.1, 0.45);
  o.scuffs = true;
  o.scuff_darkness = u(0.05, 0.3);
  o.oil = true;
  o.oil_darkness = u(0.2, 0.6);
  o.lux = u(150.0, 1500.0);
  o.exposure_reference_lux = o.lux * u(0.8, 1.3);  // auto exposure misses a little
  o.illumination_gradient = true;
  o.gradient_fraction = u(0.0, 0.5);
  o.shadows = chance(0.5);
  o.shadow_factor = u(0.3, 0.8);
  o.shadow_cover = u(0.1, 0.4);
  o.glare = true;
  o.glare_peak_dn = u(40.0, 250.0);
  o.glare_sigma_m = u(0.03, 0.2);
  o.luminaire_spacing_x_m = u(2.0, 8.0);
  o.luminaire_spacing_y_m = u(2.0, 6.0);
  if (chance(0.5)) {
    o.glare_row_pitch_m = u(0.1, 0.4);
    o.glare_row_length_m = u(1.0, std::min(4.0, o.luminaire_spacing_x_m));
  }
  o.cast_shadows = true;
  o.cast_shadow_factor = u(0.3, 0.75);
  o.cast_shadow_cover = u(0.05, 0.3);
  o.shadow_penumbra_m = u(0.003, 0.05);
  o.vehicle_shadow = chance(0.6);
  o.vehicle_shadow_factor = u(0.4, 0.8);
  o.luminaire_height_m = u(5.0, 12.0);
  o.tire_marks = true;
  o.tire_mark_darkness = u(0.05, 0.3);
  o.tire_mark_density = u(0.5, 3.0);
  o.patches = true;
  o.patch_contrast = u(0.05, 0.3);
  o.patch_cover = u(0.03, 0.15);
  o.wet = chance(0.4);
  o.wet_darkness = u(0.15, 0.45);
  o.wet_cover = u(0.05, 0.2);
  o.wet_glare_gain = u(0.5, 2.0);
  o.motion_blur = true;
  o.exposure_s = u(0.001, 0.008);
  o.noise = true;
  o.read_noise_dn = u(1.0, 4.0);
  o.electrons_per_dn = u(15.0, 60.0);
  o.standing_objects = true;
  o.clutter_per_100m = u(20.0, 60.0);
  return o;
}

}  // namespace groundline::sim
