// Internals of the floor renderer (floor_camera.h): the pixel-to-floor table,
// the marking strokes with their grid index, and the procedural floor fields.
#ifndef GROUNDLINE_SIM_SRC_FLOOR_CAMERA_INTERNAL_H_
#define GROUNDLINE_SIM_SRC_FLOOR_CAMERA_INTERNAL_H_

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "groundline/sim/floor_camera.h"

namespace groundline::sim::internal {

// Per pixel: its centre's floor point in base_link and the columns of the
// affine map d(floor)/d(u), d(floor)/d(v) (metres per pixel). valid = 0 for
// pixels that show the wall.
struct PixelFloorTable {
  int width_px = 0;
  int height_px = 0;
  std::vector<float> x_m, y_m, dxu, dyu, dxv, dyv;
  // Half the sum of the affine columns' lengths: a pixel's footprint radius.
  std::vector<float> foot_m;
  std::vector<std::uint8_t> valid;
  // Image tiles of kTile x kTile pixels: centre and radius of the floor
  // points of the tile's pixels (base_link), for culling markings per tile.
  static constexpr int kTile = 32;
  int tiles_x = 0, tiles_y = 0;
  std::vector<float> tile_cx_m, tile_cy_m, tile_radius_m;
  int floor_pixels = 0;
};

core::Result<PixelFloorTable> BuildPixelFloorTable(const calibration::CameraModel& camera,
                                                   const calibration::CameraMount& mount,
                                                   double max_floor_range_m);

// A straight piece of a marking: the rectangle of half width half_width_m
// around the segment a-b (map frame), with flat ends.
struct Stroke {
  Vector2 a_m = Vector2::Zero();
  Vector2 dir = Vector2::UnitX();  // unit, a -> b
  double length_m = 0.0;
  double half_width_m = 0.0;
  int marking = 0;  // index into World::markings
};

// Signed distance from p to the stroke's rectangle (negative inside).
double StrokeSignedDistance(const Stroke& s, const Vector2& p_m);

// StrokeSignedDistance where it is at most `cap`; elsewhere some value above
// `cap`. A test `d < x` or `d <= x` with x <= cap gives the same answer as on
// the exact distance, without its square root for points off a corner.
inline double StrokeSignedDistanceCapped(const Stroke& s, const Vector2& p_m, double cap) {
  const Vector2 d = p_m - s.a_m;
  const double along = d.dot(s.dir);
  const double across = std::abs(s.dir.x() * d.y() - s.dir.y() * d.x());
  const double ex = std::max(-along, along - s.length_m);  // > 0 beyond an end
  const double ey = across - s.half_width_m;
  // Off a corner the distance is hypot(ex, ey) >= max(ex, ey).
  if (ex <= 0.0 || ey <= 0.0 || ex > cap || ey > cap) return std::max(ex, ey);
  return std::hypot(ex, ey);
}

// Splits markings into strokes (dashes for dashed tape; interior polyline
// vertices extend the adjoining segments by the half width so corners close).
std::vector<Stroke> MakeStrokes(const World& world);

// A uniform grid over the strokes' bounding boxes.
class StrokeGrid {
 public:
  StrokeGrid(std::vector<Stroke> strokes, double cell_m);
  // Indices (ascending, unique) of strokes that may come within radius_m of
  // centre_m; appends to *out after clearing it.
  void Query(const Vector2& centre_m, double radius_m, std::vector<int>* out) const;
  const std::vector<Stroke>& strokes() const { return strokes_; }

 private:
  std::vector<Stroke> strokes_;
  double cell_m_;
  Vector2 origin_m_ = Vector2::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> cells_;
};

// Procedural, seeded fields over the map plane.
inline std::uint32_t HashU32(std::int64_t x, std::int64_t y, std::uint32_t seed) {
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B185EBCA87ULL ^
                    static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4FULL ^
                    (static_cast<std::uint64_t>(seed) << 17);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return static_cast<std::uint32_t>(h);
}

// Value noise in [0, 1] with lattice spacing 1 (smoothstep interpolation).
inline float ValueNoise(double x, double y, std::uint32_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const double tx = x - fx, ty = y - fy;
  const double sx = tx * tx * (3.0 - 2.0 * tx), sy = ty * ty * (3.0 - 2.0 * ty);
  constexpr double kScale = 1.0 / 4294967296.0;
  const double v00 = HashU32(ix, iy, seed) * kScale, v10 = HashU32(ix + 1, iy, seed) * kScale;
  const double v01 = HashU32(ix, iy + 1, seed) * kScale;
  const double v11 = HashU32(ix + 1, iy + 1, seed) * kScale;
  return static_cast<float>((v00 + sx * (v10 - v00)) * (1.0 - sy) + (v01 + sx * (v11 - v01)) * sy);
}

// Sum of octaves (each half the scale and amplitude of the previous), in [0, 1].
float Fbm(double x, double y, int octaves, std::uint32_t seed);

// The floor's low-frequency fields (features >= ~10 cm) at one point. The
// renderer evaluates them on a coarse pixel grid and interpolates them
// bilinearly; thresholds that make hard edges (shadow, oil) are applied after
// the interpolation, so the edges stay sharp.
struct CoarseFields {
  float texture = 0.5f;     // coarse concrete octaves, [0, 1]
  float scuff_mask = 0.0f;  // where scuffs occur, [0, 1]
  float oil = 0.0f;         // oil field before its threshold
  float gradient = 0.5f;    // illumination gradient field
  float shadow = 0.0f;      // shadow field before its threshold
  float glare = 0.0f;       // DN
  float wet = 0.0f;         // wet field before its threshold
  static constexpr int kCount = 7;
};

// The seed of the floor's procedural fields for these options.
inline std::uint32_t FieldSeed(const FloorRenderOptions& o) {
  return static_cast<std::uint32_t>(o.seed ^ (o.seed >> 32));
}

// Registers item `a` in the cells of a periodic tile (`cells` per side) onto
// which the grid cells [x0, x1] x [y0, y1] fold (floor division), as the entry
// a * 9 + (sx + 1) + 3 (sy + 1), (sx, sy) the tile copy the grid cell lies in;
// cells of copies beyond the neighbouring ones are skipped, and an entry equal
// to its cell's last one is not repeated. A point p of a cell then meets the
// item at p + (sx, sy) * period.
void RegisterOnTile(std::uint32_t a, std::int64_t x0, std::int64_t x1, std::int64_t y0,
                    std::int64_t y1, int cells,
                    std::vector<std::vector<std::uint32_t>>* cell_entries);

// Tire scuffs: curved dark streaks of random orientation (floor_camera.h).
// Arcs of radius 1-4 m (either turn), 0.8-3 m long, 2-4 cm wide with soft
// edges, tapering at both ends, of strength 0.6-1; their density makes the
// same mean darkening (~7.5 % of the scuff mask's area at full darkness) as the
// former straight streaks. Generated once per seed on a 64 m periodic tile
// (arcs wrap across its border), indexed by 25 cm cells; the scuff mask's
// non-periodic 4 m patches hide the period.
class ScuffField {
 public:
  // No arcs (Darkening 0) unless enabled.
  ScuffField(std::uint32_t seed, bool enabled);
  // Darkening in [0, 1] at p (1: a full scuff's centre): the maximum over the arcs.
  float Darkening(const Vector2& p_m) const;

  static constexpr double kPeriodM = 64.0;
  static constexpr double kCellM = 0.25;
  // Expected mean darkening of the arcs (the former streaks': 0.0747).
  static constexpr double kMeanDarkening = 0.0747;

 private:
  struct Arc {
    Vector2 centre_m;  // centre of curvature
    Vector2 mid_dir;   // unit, centre -> the arc's midpoint
    double radius_m;
    double half_angle_rad;
    double cos_half_angle;  // cos(half_angle_rad)
    double half_width_m;
    float strength;
  };
  float ArcDarkening(const Arc& arc, const Vector2& p_m) const;

  std::vector<Arc> arcs_;
  int cells_ = 0;  // per side of the tile
  // Per cell: entries arc * 9 + shift, shift = (sx + 1) + 3 (sy + 1) for the
  // arc's copy moved by (sx, sy) * kPeriodM.
  std::vector<std::vector<std::uint32_t>> cell_entries_;
};

// An oriented rectangle of the straight nuisances: centre, unit direction of
// its length, half sizes, and two per-rectangle values (their meaning depends
// on the field: a shadow's or patch's factor, a tire mark's strength and seed).
struct TileRect {
  Vector2 centre_m = Vector2::Zero();
  Vector2 dir = Vector2::UnitX();
  double half_length_m = 0.0;
  double half_width_m = 0.0;
  float value = 0.0f;
  float value2 = 0.0f;
};

// Oriented rectangles on a periodic tile of kPeriodM (as ScuffField), indexed
// by kCellM cells; a query at p visits every rectangle copy that may lie within
// margin_m of p.
class RectTile {
 public:
  RectTile() = default;
  RectTile(std::vector<TileRect> rects, double margin_m);
  bool empty() const { return rects_.empty(); }
  const std::vector<TileRect>& rects() const { return rects_; }
  // fn(rect, along, across): p in the frame of the rectangle copy (metres from
  // its centre along dir and to its left).
  template <typename Fn>
  void ForEachNear(const Vector2& p_m, Fn&& fn) const {
    if (rects_.empty()) return;
    const Vector2 wrapped(p_m.x() - kPeriodM * std::floor(p_m.x() / kPeriodM),
                          p_m.y() - kPeriodM * std::floor(p_m.y() / kPeriodM));
    const int cx = std::clamp(static_cast<int>(wrapped.x() / kCellM), 0, kCells - 1);
    const int cy = std::clamp(static_cast<int>(wrapped.y() / kCellM), 0, kCells - 1);
    for (const std::uint32_t entry : cells_[static_cast<std::size_t>(cy) * kCells + cx]) {
      const int shift = static_cast<int>(entry % 9);
      const TileRect& r = rects_[entry / 9];
      const Vector2 d = wrapped + kPeriodM * Vector2(shift % 3 - 1, shift / 3 - 1) - r.centre_m;
      fn(r, d.dot(r.dir), r.dir.x() * d.y() - r.dir.y() * d.x());
    }
  }

  static constexpr double kPeriodM = 64.0;
  static constexpr double kCellM = 0.5;
  static constexpr int kCells = 128;

 private:
  std::vector<TileRect> rects_;
  std::vector<std::vector<std::uint32_t>> cells_;  // entries rect * 9 + shift
};

// The rectangles of each straight nuisance for these options (empty when off).
RectTile MakeCastShadows(const FloorRenderOptions& o, std::uint32_t seed);
RectTile MakeTireMarks(const FloorRenderOptions& o, std::uint32_t seed);
RectTile MakePatches(const FloorRenderOptions& o, std::uint32_t seed);

// The luminaire of grid cell (ix, iy): its position on the floor plane.
Vector2 LuminaireAt(const FloorRenderOptions& o, std::uint32_t seed, std::int64_t ix,
                    std::int64_t iy);

// 1 inside, 0 outside, with a smoothstep over `penumbra_m` centred on the
// boundary, for a signed distance (negative inside).
inline float SoftInside(double signed_distance_m, double penumbra_m) {
  const double t = std::clamp(0.5 - signed_distance_m / penumbra_m, 0.0, 1.0);
  return static_cast<float>(t * t * (3.0 - 2.0 * t));
}

// Signed distance from (along, across) to a centred rectangle of these half sizes.
inline double RectSignedDistance(double along, double across, double half_length,
                                 double half_width) {
  const double ex = std::abs(along) - half_length, ey = std::abs(across) - half_width;
  if (ex <= 0.0 || ey <= 0.0) return std::max(ex, ey);
  return std::hypot(ex, ey);
}

// SoftInside(RectSignedDistance(...), penumbra_m), without the square root
// where the point is at least half a penumbra outside (SoftInside is 0 there,
// and the distance is at least max(ex, ey)).
inline float SoftInsideRect(double along, double across, double half_length, double half_width,
                            double penumbra_m) {
  const double ex = std::abs(along) - half_length, ey = std::abs(across) - half_width;
  if (ex >= 0.5 * penumbra_m || ey >= 0.5 * penumbra_m) return 0.0f;
  return SoftInside(RectSignedDistance(along, across, half_length, half_width), penumbra_m);
}

// Light multiplier (<= 1) of the vehicle's shadow (a convex polygon in
// base_link, counter-clockwise) at the base_link point q.
float VehicleShadowLight(const std::vector<Vector2>& polygon, const Vector2& q_m, double factor,
                         double penumbra_m);

struct FloorFields {
  explicit FloorFields(const FloorRenderOptions& options);
  CoarseFields Coarse(const Vector2& p_m) const;
  // Concrete reflectance (texture, scuffs, oil, tire marks, patches, wet) at p.
  float Concrete(const Vector2& p_m, const CoarseFields& c) const;
  // True when the tape of a marking with this wear fraction is worn away at p.
  bool Worn(const Vector2& p_m, double wear_fraction) const;
  // Relative illumination (gradient, shadow patches, cast shadows) at p, 1 = options.lux.
  float Light(const Vector2& p_m, const CoarseFields& c) const;
  // The glare added at p (DN): the luminaires' spots, stronger on wet floor.
  float GlareAt(const CoarseFields& c) const;

  FloorRenderOptions options;
  std::uint32_t seed;
  std::vector<float> wear_quantiles;  // sorted samples of the wear field
  float shadow_threshold = 1.0f;
  float wet_threshold = 1.0f;
  ScuffField scuff_field;
  RectTile cast_shadows, tire_marks, patches;

 private:
  float Glare(const Vector2& p_m) const;
};

// The image's extent in normalized coordinates (x/z, y/z) with a margin: a
// point in front of the camera beyond one of these bounds projects off the
// w x h image (the lens is monotonic). The whole projectable cone when the
// border does not unproject.
struct ImageCone {
  double x_lo, x_hi, y_lo, y_hi;
};
ImageCone ComputeImageCone(const calibration::CameraModel& camera, int w, int h);

// Draws the occluders over the image `dn` (w x h floats) by forward projection
// (floor_camera.h, step 4); gain is DN per unit reflectance; `cone` is the
// camera's ComputeImageCone.
void DrawOccluders(const calibration::CameraModel& camera, const calibration::CameraMount& mount,
                   const ImageCone& cone, const core::SE2& T_map_base,
                   const std::vector<Occluder>& occluders, double gain, int w, int h,
                   std::vector<float>* dn);

}  // namespace groundline::sim::internal

#endif  // GROUNDLINE_SIM_SRC_FLOOR_CAMERA_INTERNAL_H_
