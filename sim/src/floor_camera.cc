// The floor renderer: per-frame shading of the precomputed pixel floor points.
#include "groundline/sim/floor_camera.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <type_traits>

#include "floor_camera_internal.h"
#include "groundline/sim/floor_nuisances.h"
#include "options_check.h"

namespace groundline::sim {

using internal::CheckRange;
using internal::FirstError;

core::Status FloorRenderOptions::Validate() const {
  const char* o = "FloorRenderOptions";
  return FirstError({
      CheckRange(o, "supersampling", supersampling, 1, 8),
      CheckRange(o, "max_floor_range_m", max_floor_range_m, 0.1, 1000.0),
      CheckRange(o, "wall_dn", wall_dn, 0.0, 255.0),
      CheckRange(o, "concrete_reflectance", concrete_reflectance, 0.0, 1.0),
      CheckRange(o, "tape_reflectance_scale", tape_reflectance_scale, 0.0, 1.0),
      CheckRange(o, "texture_contrast", texture_contrast, 0.0, 1.0),
      CheckRange(o, "scuff_darkness", scuff_darkness, 0.0, 1.0),
      CheckRange(o, "oil_darkness", oil_darkness, 0.0, 1.0),
      CheckRange(o, "lux", lux, 1.0, 200000.0),
      CheckRange(o, "exposure_reference_lux", exposure_reference_lux, 1.0, 200000.0),
      CheckRange(o, "gradient_fraction", gradient_fraction, 0.0, 0.9),
      CheckRange(o, "shadow_factor", shadow_factor, 0.0, 1.0),
      CheckRange(o, "shadow_cover", shadow_cover, 0.0, 1.0),
      CheckRange(o, "glare_peak_dn", glare_peak_dn, 0.0, 1000.0),
      CheckRange(o, "glare_sigma_m", glare_sigma_m, 0.005, 2.0),
      CheckRange(o, "luminaire_spacing_x_m", luminaire_spacing_x_m, 0.5, 100.0),
      CheckRange(o, "luminaire_spacing_y_m", luminaire_spacing_y_m, 0.5, 100.0),
      CheckRange(o, "glare_row_pitch_m", glare_row_pitch_m, 0.0, 10.0),
      // A row stays within its luminaire's cell and the two beside it.
      CheckRange(o, "glare_row_length_m", glare_row_length_m, 0.0,
                 glare_row_pitch_m > 0.0 ? luminaire_spacing_x_m : 1e6),
      CheckRange(o, "cast_shadow_factor", cast_shadow_factor, 0.0, 1.0),
      CheckRange(o, "cast_shadow_cover", cast_shadow_cover, 0.0, 1.0),
      CheckRange(o, "shadow_penumbra_m", shadow_penumbra_m, 1e-4, 0.5),
      CheckRange(o, "vehicle_shadow_factor", vehicle_shadow_factor, 0.0, 1.0),
      CheckRange(o, "luminaire_height_m", luminaire_height_m, 0.5, 100.0),
      CheckRange(o, "vehicle_front_m", vehicle_front_m, vehicle_back_m, 20.0),
      CheckRange(o, "vehicle_back_m", vehicle_back_m, -20.0, vehicle_front_m),
      CheckRange(o, "vehicle_half_width_m", vehicle_half_width_m, 0.0, 10.0),
      CheckRange(o, "vehicle_height_m", vehicle_height_m, 0.0, luminaire_height_m),
      CheckRange(o, "tire_mark_darkness", tire_mark_darkness, 0.0, 1.0),
      CheckRange(o, "tire_mark_density", tire_mark_density, 0.0, 20.0),
      CheckRange(o, "patch_contrast", patch_contrast, 0.0, 0.9),
      CheckRange(o, "patch_cover", patch_cover, 0.0, 1.0),
      CheckRange(o, "wet_darkness", wet_darkness, 0.0, 1.0),
      CheckRange(o, "wet_glare_gain", wet_glare_gain, 0.0, 20.0),
      CheckRange(o, "wet_cover", wet_cover, 0.0, 1.0),
      CheckRange(o, "clutter_per_100m", clutter_per_100m, 0.0, 1000.0),
      CheckRange(o, "exposure_s", exposure_s, 0.0, 0.1),
      CheckRange(o, "read_noise_dn", read_noise_dn, 0.0, 50.0),
      CheckRange(o, "electrons_per_dn", electrons_per_dn, 0.1, 1e6),
  });
}

FloorRenderOptions FloorRenderOptions::Ideal() {
  FloorRenderOptions o;
  o.texture = o.wear = o.scuffs = o.oil = false;
  o.illumination_gradient = o.shadows = o.glare = o.motion_blur = o.noise = false;
  o.occlusion = false;
  o.cast_shadows = o.vehicle_shadow = o.tire_marks = o.patches = o.wet = false;
  return o;
}

struct FloorRenderer::Impl {
  Impl(const calibration::CameraModel& c, const calibration::CameraMount& m,
       internal::PixelFloorTable t, internal::StrokeGrid g, const FloorRenderOptions& o)
      : camera(c),
        mount(m),
        table(std::move(t)),
        grid(std::move(g)),
        fields(o),
        image_cone(internal::ComputeImageCone(c, table.width_px, table.height_px)) {}
  calibration::CameraModel camera;
  calibration::CameraMount mount;
  internal::PixelFloorTable table;
  internal::StrokeGrid grid;
  internal::FloorFields fields;
  internal::ImageCone image_cone;
  std::vector<float> marking_reflectance;
  std::vector<double> marking_wear;
  // Paint order: where markings overlap the one of the highest layer shows.
  // Joints lie below every painted marking (tape and paint are laid over
  // the saw cuts, as the layout PNG draws them and as the ground truth of
  // perception::VisibleMarkingLines assumes); otherwise later markings show.
  std::vector<int> layer;
};

core::Result<FloorRenderer> FloorRenderer::Create(const World& world,
                                                  const calibration::CameraModel& camera,
                                                  const calibration::CameraMount& mount,
                                                  const FloorRenderOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  if (core::Status s = mount.Validate(); !s.ok()) return s.WithContext("floor camera mount");
  core::Result<internal::PixelFloorTable> table =
      internal::BuildPixelFloorTable(camera, mount, options.max_floor_range_m);
  if (!table.ok()) return table.status();
  auto impl =
      std::make_shared<Impl>(camera, mount, std::move(table).value(),
                             internal::StrokeGrid(internal::MakeStrokes(world), 1.0), options);
  for (const FloorMarking& m : world.markings) {
    // Linear-sRGB luminance of the colour (Rec. 709 weights).
    const std::array<int, 3> rgb = MarkingColourRgb(m.colour);
    double y = 0.0;
    const double w[3] = {0.2126, 0.7152, 0.0722};
    for (int c = 0; c < 3; ++c) {
      const double s = rgb[c] / 255.0;
      y += w[c] * (s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
    }
    impl->marking_reflectance.push_back(static_cast<float>(y * options.tape_reflectance_scale));
    impl->marking_wear.push_back(m.wear_fraction);
    const int index = static_cast<int>(impl->layer.size());
    impl->layer.push_back(
        m.kind == MarkingKind::kJoint ? index : index + static_cast<int>(world.markings.size()));
  }
  return FloorRenderer(std::move(impl));
}

const calibration::CameraModel& FloorRenderer::camera() const { return impl_->camera; }
const calibration::CameraMount& FloorRenderer::mount() const { return impl_->mount; }
double FloorRenderer::FloorPixelFraction() const {
  return static_cast<double>(impl_->table.floor_pixels) /
         (static_cast<double>(impl_->table.width_px) * impl_->table.height_px);
}

namespace {

// Motion blur: each pixel averages the sharp image along its own image motion
// during the exposure, d_px = (d floor / d pixel)^-1 * (floor displacement).
std::vector<float> MotionBlur(const internal::PixelFloorTable& t, const std::vector<float>& sharp,
                              const BaseVelocity& vel, double exposure_s) {
  std::vector<float> out = sharp;
  const int w = t.width_px, h = t.height_px;
  // Bilinear sample of the sharp image; `Clamp` keeps (u, v) on the image, which
  // the caller may skip when the whole blur segment lies in [0, w-2] x [0, h-2]
  // (the clamps are then no-ops, so both give the same value).
  const auto sample = [&](auto clamp, double u, double v) {
    if constexpr (decltype(clamp)::value) {
      u = std::clamp(u, 0.0, w - 1.0);
      v = std::clamp(v, 0.0, h - 1.0);
    }
    int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
    if constexpr (decltype(clamp)::value) {
      u0 = std::min(u0, w - 2);
      v0 = std::min(v0, h - 2);
    }
    const double a = u - u0, b = v - v0;
    const float* r0 = &sharp[static_cast<std::size_t>(v0) * w + u0];
    const float* r1 = r0 + w;
    return (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
  };
  // Sample k of n lies at offset (k + 0.5) / n - 0.5 of the blur segment.
  constexpr int kMaxSamples = 64;
  static const std::vector<double> offsets = [] {
    std::vector<double> o(static_cast<std::size_t>(kMaxSamples + 1) * kMaxSamples);
    for (int n = 1; n <= kMaxSamples; ++n) {
      for (int k = 0; k < n; ++k) {
        o[static_cast<std::size_t>(n) * kMaxSamples + k] = (k + 0.5) / n - 0.5;
      }
    }
    return o;
  }();
  const auto blur = [&](auto clamp, int u, int v, double du, double dv, int n) {
    const double* s = &offsets[static_cast<std::size_t>(n) * kMaxSamples];
    double sum = 0.0;
    for (int k = 0; k < n; ++k) sum += sample(clamp, u + s[k] * du, v + s[k] * dv);
    return sum;
  };
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      if (!t.valid[i]) continue;
      // A static floor point's velocity in base_link: -(v e_x + omega x p).
      const double fx = (-vel.forward_mps + vel.yaw_rate_radps * t.y_m[i]) * exposure_s;
      const double fy = (-vel.yaw_rate_radps * t.x_m[i]) * exposure_s;
      const double a = t.dxu[i], b = t.dxv[i], c = t.dyu[i], d = t.dyv[i];
      const double det = a * d - b * c;
      if (std::abs(det) < 1e-18) continue;
      const double du = (d * fx - b * fy) / det, dv = (-c * fx + a * fy) / det;
      // The blur length decides only the sample count: the plain square root
      // does, except within a hair of a threshold, where hypot's value decides.
      double len = std::sqrt(du * du + dv * dv);
      if (std::abs(len - 0.25) < 1e-9 * (1.0 + len) ||
          std::abs(len - std::round(len)) < 1e-9 * (1.0 + len)) {
        len = std::hypot(du, dv);
      }
      if (len < 0.25) continue;
      const int n = std::min(kMaxSamples, static_cast<int>(std::ceil(len)) + 1);
      const double half_u = 0.5 * std::abs(du), half_v = 0.5 * std::abs(dv);
      const bool inside =
          u - half_u >= 0.0 && u + half_u <= w - 2.0 && v - half_v >= 0.0 && v + half_v <= h - 2.0;
      const double sum = inside ? blur(std::false_type{}, u, v, du, dv, n)
                                : blur(std::true_type{}, u, v, du, dv, n);
      out[i] = static_cast<float>(sum / n);
    }
  }
  return out;
}

}  // namespace

namespace {

constexpr int kCoarseStep = 8;  // pixels between coarse-field nodes

// The coarse fields at every kCoarseStep-th pixel (clamped to the last
// row/column); nodes on the wall are flagged invalid.
struct CoarseGrid {
  int nx = 0, ny = 0;
  std::vector<internal::CoarseFields> nodes;
  std::vector<std::uint8_t> valid;
};

CoarseGrid EvaluateCoarse(const internal::PixelFloorTable& t, const internal::FloorFields& f,
                          const Eigen::Matrix2d& R, const Vector2& tr) {
  CoarseGrid g;
  g.nx = (t.width_px - 2) / kCoarseStep + 2;
  g.ny = (t.height_px - 2) / kCoarseStep + 2;
  g.nodes.resize(static_cast<std::size_t>(g.nx) * g.ny);
  g.valid.assign(g.nodes.size(), 0);
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const int u = std::min(i * kCoarseStep, t.width_px - 1);
      const int v = std::min(j * kCoarseStep, t.height_px - 1);
      const std::size_t pi = static_cast<std::size_t>(v) * t.width_px + u;
      if (!t.valid[pi]) continue;
      const std::size_t ni = static_cast<std::size_t>(j) * g.nx + i;
      g.nodes[ni] = f.Coarse(tr + R * Vector2(t.x_m[pi], t.y_m[pi]));
      g.valid[ni] = 1;
    }
  }
  return g;
}

// Bilinear interpolation of the coarse fields at pixel (u, v); false when a
// surrounding node is on the wall.
bool InterpolateCoarse(const CoarseGrid& g, int u, int v, int w, int h,
                       internal::CoarseFields* out) {
  const int i0 = u / kCoarseStep, j0 = v / kCoarseStep;
  const int i1 = std::min(i0 + 1, g.nx - 1), j1 = std::min(j0 + 1, g.ny - 1);
  const int u0 = std::min(i0 * kCoarseStep, w - 1), u1 = std::min(i1 * kCoarseStep, w - 1);
  const int v0 = std::min(j0 * kCoarseStep, h - 1), v1 = std::min(j1 * kCoarseStep, h - 1);
  const float a = u1 > u0 ? static_cast<float>(u - u0) / static_cast<float>(u1 - u0) : 0.0f;
  const float b = v1 > v0 ? static_cast<float>(v - v0) / static_cast<float>(v1 - v0) : 0.0f;
  const std::size_t n00 = static_cast<std::size_t>(j0) * g.nx + i0,
                    n10 = static_cast<std::size_t>(j0) * g.nx + i1,
                    n01 = static_cast<std::size_t>(j1) * g.nx + i0,
                    n11 = static_cast<std::size_t>(j1) * g.nx + i1;
  if (!(g.valid[n00] && g.valid[n10] && g.valid[n01] && g.valid[n11])) return false;
  static_assert(sizeof(internal::CoarseFields) == internal::CoarseFields::kCount * sizeof(float));
  const float* f00 = &g.nodes[n00].texture;
  const float* f10 = &g.nodes[n10].texture;
  const float* f01 = &g.nodes[n01].texture;
  const float* f11 = &g.nodes[n11].texture;
  float* o = &out->texture;
  for (int k = 0; k < internal::CoarseFields::kCount; ++k) {
    o[k] = (1 - b) * ((1 - a) * f00[k] + a * f10[k]) + b * ((1 - a) * f01[k] + a * f11[k]);
  }
  return true;
}

// Standard normal deviates from a seeded xorshift generator through a table of
// the inverse normal CDF (4096 equiprobable bins): fast and deterministic.
class FastNormal {
 public:
  explicit FastNormal(std::uint64_t seed) : state_(seed | 1) {
    static const std::vector<float> table = [] {
      std::vector<float> t(4096);
      for (std::size_t i = 0; i < t.size(); ++i) {
        const double p = (static_cast<double>(i) + 0.5) / static_cast<double>(t.size());
        // Acklam-free inversion by bisection of erfc (runs once).
        double lo = -8.0, hi = 8.0;
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
        }
        t[i] = static_cast<float>(0.5 * (lo + hi));
      }
      return t;
    }();
    table_ = &table;
  }
  float operator()() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 7;
    state_ ^= state_ << 17;
    return (*table_)[(state_ >> 20) & 4095];
  }

 private:
  std::uint64_t state_;
  const std::vector<float>* table_;
};

}  // namespace

GreyImage FloorRenderer::Render(const core::SE2& T_map_base, const BaseVelocity& velocity,
                                std::uint64_t frame_index,
                                const std::vector<Occluder>& occluders) const {
  const Impl& im = *impl_;
  const internal::PixelFloorTable& t = im.table;
  const FloorRenderOptions& o = im.fields.options;
  const int w = t.width_px, h = t.height_px;
  const double gain = 255.0 * o.lux / o.exposure_reference_lux;
  const Eigen::Matrix2d R = T_map_base.Rotation();
  const Vector2 tr = T_map_base.translation();
  const int S = o.supersampling;
  const auto& strokes = im.grid.strokes();
  const CoarseGrid coarse = EvaluateCoarse(t, im.fields, R, tr);
  const std::optional<std::vector<Vector2>> vehicle_shadow = VehicleShadowPolygon(o, T_map_base);

  std::vector<float> dn(static_cast<std::size_t>(w) * h, static_cast<float>(o.wall_dn));
  std::vector<int> cand;
  constexpr int kT = internal::PixelFloorTable::kTile;
  for (int ty = 0; ty < t.tiles_y; ++ty) {
    for (int tx = 0; tx < t.tiles_x; ++tx) {
      const std::size_t ti = static_cast<std::size_t>(ty) * t.tiles_x + tx;
      if (t.tile_radius_m[ti] < 0.0f) continue;
      im.grid.Query(tr + R * Vector2(t.tile_cx_m[ti], t.tile_cy_m[ti]), t.tile_radius_m[ti], &cand);
      for (int v = ty * kT; v < std::min(h, (ty + 1) * kT); ++v) {
        for (int u = tx * kT; u < std::min(w, (tx + 1) * kT); ++u) {
          const std::size_t i = static_cast<std::size_t>(v) * w + u;
          if (!t.valid[i]) continue;
          const Vector2 p = tr + R * Vector2(t.x_m[i], t.y_m[i]);
          internal::CoarseFields cf;
          if (!InterpolateCoarse(coarse, u, v, w, h, &cf)) cf = im.fields.Coarse(p);
          const float concrete = im.fields.Concrete(p, cf);
          // Marking coverage: one sample unless the pixel straddles an edge.
          const double foot = t.foot_m[i];
          int top = -1;  // the top marking (highest layer) fully covering the pixel
          bool edge = false;
          const auto above = [&](int m, int than) {
            return than < 0 ||
                   im.layer[static_cast<std::size_t>(m)] > im.layer[static_cast<std::size_t>(than)];
          };
          for (const int k : cand) {
            const double sd = internal::StrokeSignedDistanceCapped(strokes[k], p, foot);
            if (sd < -foot) {
              if (above(strokes[k].marking, top)) top = strokes[k].marking;
            } else if (sd <= foot) {
              edge = true;
            }
          }
          const auto marking_refl = [&](int m) {
            return im.fields.Worn(p, im.marking_wear[m]) ? concrete : im.marking_reflectance[m];
          };
          double refl;
          if (!edge) {
            refl = top >= 0 ? marking_refl(top) : concrete;
          } else {
            const Vector2 du = R * Vector2(t.dxu[i], t.dyu[i]);
            const Vector2 dv = R * Vector2(t.dxv[i], t.dyv[i]);
            double sum = 0.0;
            for (int sy = 0; sy < S; ++sy) {
              for (int sx = 0; sx < S; ++sx) {
                const Vector2 q = p + ((sx + 0.5) / S - 0.5) * du + ((sy + 0.5) / S - 0.5) * dv;
                int m = -1;
                for (const int k : cand) {
                  if (internal::StrokeSignedDistanceCapped(strokes[k], q, 0.0) <= 0.0 &&
                      above(strokes[k].marking, m)) {
                    m = strokes[k].marking;
                  }
                }
                sum += m >= 0 ? marking_refl(m) : concrete;
              }
            }
            refl = sum / (S * S);
          }
          float light = im.fields.Light(p, cf);
          if (vehicle_shadow) {
            light *= internal::VehicleShadowLight(*vehicle_shadow, Vector2(t.x_m[i], t.y_m[i]),
                                                  o.vehicle_shadow_factor, o.shadow_penumbra_m);
          }
          dn[i] = static_cast<float>(gain * refl * light + im.fields.GlareAt(cf));
        }
      }
    }
  }
  if (o.motion_blur && o.exposure_s > 0.0) dn = MotionBlur(t, dn, velocity, o.exposure_s);
  if (o.occlusion && !occluders.empty()) {
    internal::DrawOccluders(im.camera, im.mount, im.image_cone, T_map_base, occluders, gain, w, h,
                            &dn);
  }

  GreyImage image;
  image.width_px = w;
  image.height_px = h;
  image.pixels.resize(dn.size());
  FastNormal normal(o.seed * 0x9E3779B97F4A7C15ULL + frame_index * 0xD1B54A32D192ED03ULL + 7);
  const auto read_var = static_cast<float>(o.read_noise_dn * o.read_noise_dn);
  const auto inv_epd = static_cast<float>(1.0 / o.electrons_per_dn);
  for (std::size_t i = 0; i < dn.size(); ++i) {
    float value = std::min(dn[i], 255.0f);
    if (o.noise) value += std::sqrt(read_var + std::max(value, 0.0f) * inv_epd) * normal();
    image.pixels[i] = static_cast<std::uint8_t>(std::clamp(value, 0.0f, 255.0f) + 0.5f);
  }
  return image;
}

}  // namespace groundline::sim
