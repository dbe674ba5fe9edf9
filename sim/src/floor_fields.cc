// Marking strokes with their grid index, and the seeded procedural floor fields.
#include <algorithm>
#include <cmath>
#include <limits>

#include "floor_camera_internal.h"

namespace groundline::sim::internal {

double StrokeSignedDistance(const Stroke& s, const Vector2& p_m) {
  return StrokeSignedDistanceCapped(s, p_m, std::numeric_limits<double>::infinity());
}

namespace {

void AddStroke(const Vector2& a, const Vector2& b, double half_width_m, int marking,
               double extend_a_m, double extend_b_m, std::vector<Stroke>* out) {
  const double len = (b - a).norm();
  if (len < 1e-9) return;
  Stroke s;
  s.dir = (b - a) / len;
  s.a_m = a - extend_a_m * s.dir;
  s.length_m = len + extend_a_m + extend_b_m;
  s.half_width_m = half_width_m;
  s.marking = marking;
  out->push_back(s);
}

}  // namespace

std::vector<Stroke> MakeStrokes(const World& world) {
  std::vector<Stroke> strokes;
  for (std::size_t m = 0; m < world.markings.size(); ++m) {
    const FloorMarking& mk = world.markings[m];
    const double hw = 0.5 * mk.width_m;
    const auto& pl = mk.polyline_m;
    const int id = static_cast<int>(m);
    const bool dashed =
        mk.kind == MarkingKind::kTapeDashed && mk.dash_length_m > 0.0 && mk.gap_length_m > 0.0;
    const double period = mk.dash_length_m + mk.gap_length_m;
    double s0 = 0.0;  // arc length at the segment start
    for (std::size_t i = 1; i < pl.size(); ++i) {
      const Vector2 a = pl[i - 1], b = pl[i];
      const double len = (b - a).norm();
      if (!dashed) {
        const double ext_a = i > 1 ? hw : 0.0;
        const double ext_b = i + 1 < pl.size() ? hw : 0.0;
        AddStroke(a, b, hw, id, ext_a, ext_b, &strokes);
      } else if (len > 0.0) {
        const Vector2 dir = (b - a) / len;
        // Dashes [k * period, k * period + dash] intersected with [s0, s0 + len].
        for (double k = std::floor(s0 / period); k * period < s0 + len; k += 1.0) {
          const double d0 = std::max(k * period, s0) - s0;
          const double d1 = std::min(k * period + mk.dash_length_m, s0 + len) - s0;
          if (d1 > d0) AddStroke(a + d0 * dir, a + d1 * dir, hw, id, 0.0, 0.0, &strokes);
        }
      }
      s0 += len;
    }
  }
  return strokes;
}

StrokeGrid::StrokeGrid(std::vector<Stroke> strokes, double cell_m)
    : strokes_(std::move(strokes)), cell_m_(cell_m) {
  if (strokes_.empty()) return;
  Vector2 lo = Vector2::Constant(1e300), hi = Vector2::Constant(-1e300);
  for (const Stroke& s : strokes_) {
    const Vector2 b = s.a_m + s.length_m * s.dir;
    lo = lo.cwiseMin(s.a_m.cwiseMin(b) - Vector2::Constant(s.half_width_m));
    hi = hi.cwiseMax(s.a_m.cwiseMax(b) + Vector2::Constant(s.half_width_m));
  }
  origin_m_ = lo;
  nx_ = static_cast<int>((hi.x() - lo.x()) / cell_m_) + 1;
  ny_ = static_cast<int>((hi.y() - lo.y()) / cell_m_) + 1;
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  for (std::size_t k = 0; k < strokes_.size(); ++k) {
    const Stroke& s = strokes_[k];
    const Vector2 b = s.a_m + s.length_m * s.dir;
    const Vector2 smin = s.a_m.cwiseMin(b) - Vector2::Constant(s.half_width_m) - origin_m_;
    const Vector2 smax = s.a_m.cwiseMax(b) + Vector2::Constant(s.half_width_m) - origin_m_;
    for (int y = static_cast<int>(smin.y() / cell_m_); y <= static_cast<int>(smax.y() / cell_m_);
         ++y) {
      for (int x = static_cast<int>(smin.x() / cell_m_); x <= static_cast<int>(smax.x() / cell_m_);
           ++x) {
        const Vector2 c = origin_m_ + cell_m_ * Vector2(x + 0.5, y + 0.5);
        if (StrokeSignedDistance(s, c) > 0.7072 * cell_m_) continue;
        cells_[static_cast<std::size_t>(y) * nx_ + x].push_back(static_cast<int>(k));
      }
    }
  }
}

void StrokeGrid::Query(const Vector2& centre_m, double radius_m, std::vector<int>* out) const {
  out->clear();
  if (strokes_.empty()) return;
  const Vector2 lo = (centre_m - Vector2::Constant(radius_m) - origin_m_) / cell_m_;
  const Vector2 hi = (centre_m + Vector2::Constant(radius_m) - origin_m_) / cell_m_;
  const int x0 = std::max(0, static_cast<int>(std::floor(lo.x())));
  const int y0 = std::max(0, static_cast<int>(std::floor(lo.y())));
  const int x1 = std::min(nx_ - 1, static_cast<int>(std::floor(hi.x())));
  const int y1 = std::min(ny_ - 1, static_cast<int>(std::floor(hi.y())));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      for (const int k : cells_[static_cast<std::size_t>(y) * nx_ + x]) {
        if (StrokeSignedDistance(strokes_[k], centre_m) <= radius_m) out->push_back(k);
      }
    }
  }
  std::sort(out->begin(), out->end());
  out->erase(std::unique(out->begin(), out->end()), out->end());
}

float Fbm(double x, double y, int octaves, std::uint32_t seed) {
  double sum = 0.0, amp = 1.0, norm = 0.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * ValueNoise(x, y, seed + 977u * static_cast<std::uint32_t>(o));
    norm += amp;
    amp *= 0.5;
    x *= 2.0;
    y *= 2.0;
  }
  return static_cast<float>(sum / norm);
}

namespace {
constexpr std::uint32_t kTexture = 11, kScuffMask = 14, kOil = 15, kWear = 16, kLight = 17,
                        kShadow = 18, kWet = 20;
float SmoothStepFloat(float lo, float hi, float x) {
  const float t = std::clamp((x - lo) / (hi - lo), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}
}  // namespace

FloorFields::FloorFields(const FloorRenderOptions& o)
    : options(o),
      seed(FieldSeed(o)),
      scuff_field(seed, o.scuffs),
      cast_shadows(MakeCastShadows(o, seed)),
      tire_marks(MakeTireMarks(o, seed)),
      patches(MakePatches(o, seed)) {
  // Empirical quantiles make wear_fraction, shadow_cover and wet_cover area
  // fractions.
  constexpr int kN = 4096;
  std::vector<float> shadow, wet;
  for (int i = 0; i < kN; ++i) {
    const Vector2 p(37.3 * (i % 64) + 0.123, 41.9 * (i / 64) + 0.456);
    wear_quantiles.push_back(Fbm(p.x() / 0.2, p.y() / 0.2, 2, seed + kWear));
    shadow.push_back(Fbm(p.x() / 3.0, p.y() / 3.0, 2, seed + kShadow));
    wet.push_back(Fbm(p.x() / 2.5, p.y() / 2.5, 3, seed + kWet));
  }
  std::sort(wear_quantiles.begin(), wear_quantiles.end());
  std::sort(shadow.begin(), shadow.end());
  std::sort(wet.begin(), wet.end());
  const auto quantile = [](const std::vector<float>& v, double cover) {
    return v[static_cast<std::size_t>(std::clamp(1.0 - cover, 0.0, 1.0) * (v.size() - 1))];
  };
  shadow_threshold = quantile(shadow, o.shadow_cover);
  wet_threshold = quantile(wet, o.wet_cover);
}

CoarseFields FloorFields::Coarse(const Vector2& p) const {
  CoarseFields c;
  if (options.texture) c.texture = Fbm(p.x() / 0.8, p.y() / 0.8, 3, seed + kTexture);
  if (options.scuffs) {
    c.scuff_mask =
        SmoothStepFloat(0.55f, 0.7f, ValueNoise(p.x() / 4.0, p.y() / 4.0, seed + kScuffMask));
  }
  if (options.oil) c.oil = Fbm(p.x() / 0.6, p.y() / 0.6, 3, seed + kOil);
  if (options.illumination_gradient)
    c.gradient = ValueNoise(p.x() / 10.0, p.y() / 10.0, seed + kLight);
  if (options.shadows) c.shadow = Fbm(p.x() / 3.0, p.y() / 3.0, 2, seed + kShadow);
  if (options.wet) c.wet = Fbm(p.x() / 2.5, p.y() / 2.5, 3, seed + kWet);
  c.glare = Glare(p);
  return c;
}

float FloorFields::Concrete(const Vector2& p, const CoarseFields& c) const {
  float r = static_cast<float>(options.concrete_reflectance);
  if (options.texture) {
    const float fine = ValueNoise(p.x() / 0.01, p.y() / 0.01, seed + kTexture + 100);
    r *= 1.0f + static_cast<float>(options.texture_contrast) *
                    (1.4f * (c.texture - 0.5f) + 0.8f * (fine - 0.5f));
  }
  if (options.scuffs && c.scuff_mask > 0.0f) {
    // Curved streaks (ScuffField) in some 40 % of the floor.
    r *=
        1.0f - static_cast<float>(options.scuff_darkness) * c.scuff_mask * scuff_field.Darkening(p);
  }
  if (options.oil) {
    r *= 1.0f - static_cast<float>(options.oil_darkness) * SmoothStepFloat(0.77f, 0.79f, c.oil);
  }
  // Tire marks: value = strength, value2 = the seed of its variation along it.
  float tire = 0.0f;
  tire_marks.ForEachNear(p, [&](const TileRect& m, double along, double across) {
    const double t = std::abs(along) / m.half_length_m;
    const double a = std::abs(across) / m.half_width_m;
    if (t >= 1.0 || a >= 1.0) return;
    const float across_w = 1.0f - SmoothStepFloat(0.3f, 1.0f, static_cast<float>(a));
    const float ends = 1.0f - SmoothStepFloat(0.85f, 1.0f, static_cast<float>(t));
    const float along_w =
        0.4f + 0.6f * ValueNoise(along / 0.7, 0.0, static_cast<std::uint32_t>(m.value2));
    tire = std::max(tire, m.value * across_w * ends * along_w);
  });
  r *= 1.0f - static_cast<float>(options.tire_mark_darkness) * tire;
  // Patches: value = the reflectance factor; sharp seams (1 mm).
  patches.ForEachNear(p, [&](const TileRect& m, double along, double across) {
    const float in = SoftInsideRect(along, across, m.half_length_m, m.half_width_m, 0.001);
    r *= 1.0f + (m.value - 1.0f) * in;
  });
  if (options.wet) {
    r *= 1.0f - static_cast<float>(options.wet_darkness) *
                    SmoothStepFloat(wet_threshold - 0.01f, wet_threshold + 0.01f, c.wet);
  }
  return r;
}

bool FloorFields::Worn(const Vector2& p, double wear_fraction) const {
  if (!options.wear || wear_fraction <= 0.0) return false;
  const auto k = static_cast<std::size_t>(std::clamp(wear_fraction, 0.0, 1.0) *
                                          static_cast<double>(wear_quantiles.size() - 1));
  return Fbm(p.x() / 0.2, p.y() / 0.2, 2, seed + kWear) < wear_quantiles[k];
}

float FloorFields::Light(const Vector2& p, const CoarseFields& c) const {
  float l = 1.0f;
  if (options.illumination_gradient) {
    l *= 1.0f + static_cast<float>(options.gradient_fraction) * 2.0f * (c.gradient - 0.5f);
  }
  if (options.shadows) {
    // Hard edge: a few mm of penumbra at the field's ~0.3 /m gradient.
    const float in =
        SmoothStepFloat(shadow_threshold - 0.0005f, shadow_threshold + 0.0005f, c.shadow);
    l *= 1.0f - (1.0f - static_cast<float>(options.shadow_factor)) * in;
  }
  // Cast shadows from one light: overlapping shadows are no darker than one.
  float shade = 0.0f;
  cast_shadows.ForEachNear(p, [&](const TileRect& m, double along, double across) {
    shade = std::max(shade, SoftInsideRect(along, across, m.half_length_m, m.half_width_m,
                                           options.shadow_penumbra_m));
  });
  l *= 1.0f - (1.0f - static_cast<float>(options.cast_shadow_factor)) * shade;
  return l;
}

float FloorFields::GlareAt(const CoarseFields& c) const {
  if (!options.wet) return c.glare;
  return c.glare *
         (1.0f + static_cast<float>(options.wet_glare_gain) *
                     SmoothStepFloat(wet_threshold - 0.01f, wet_threshold + 0.01f, c.wet));
}

float FloorFields::Glare(const Vector2& p) const {
  if (!options.glare) return 0.0f;
  const double sx = options.luminaire_spacing_x_m, sy = options.luminaire_spacing_y_m;
  const double cx = std::floor(p.x() / sx), cy = std::floor(p.y() / sy);
  const double inv_s2 = 1.0 / (options.glare_sigma_m * options.glare_sigma_m);
  const double pitch = options.glare_row_pitch_m;
  // Spots of a row: k = -n..n at k * pitch from the luminaire along x.
  const int n = pitch > 0.0 ? static_cast<int>(0.5 * options.glare_row_length_m / pitch) : 0;
  float sum = 0.0f;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const Vector2 lum = LuminaireAt(options, seed, static_cast<std::int64_t>(cx) + dx,
                                      static_cast<std::int64_t>(cy) + dy);
      const double ddy = p.y() - lum.y();
      if (ddy * ddy * inv_s2 >= 25.0) continue;
      // The nearest spots only: beyond 5 sigma a spot adds nothing.
      const double rel = p.x() - lum.x();
      const int k_near = n > 0 ? static_cast<int>(std::lround(rel / pitch)) : 0;
      const int reach =
          n > 0 ? static_cast<int>(std::ceil(5.0 * options.glare_sigma_m / pitch)) : 0;
      for (int k = std::max(-n, k_near - reach); k <= std::min(n, k_near + reach); ++k) {
        const double ddx = rel - k * pitch;
        const double r2 = (ddx * ddx + ddy * ddy) * inv_s2;
        if (r2 < 25.0) sum += static_cast<float>(options.glare_peak_dn * std::exp(-0.5 * r2));
      }
    }
  }
  return sum;
}

}  // namespace groundline::sim::internal
