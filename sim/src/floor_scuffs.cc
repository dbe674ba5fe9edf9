// Curved tire scuffs on a periodic tile (ScuffField, floor_camera_internal.h).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "floor_camera_internal.h"

namespace groundline::sim::internal {
namespace {

constexpr std::uint32_t kScuffArcs = 21;
constexpr double kMinRadiusM = 1.0, kMaxRadiusM = 4.0;
constexpr double kMinLengthM = 0.8, kMaxLengthM = 3.0;
constexpr double kMinHalfWidthM = 0.010, kMaxHalfWidthM = 0.020;
constexpr double kMinStrength = 0.6, kMaxStrength = 1.0;
// Soft edges: full darkening out to kCoreFraction of the half width, then a
// smoothstep to zero; the ends taper from kTaperStart of the half length.
constexpr double kCoreFraction = 0.35;
constexpr double kTaperStart = 0.6;

double SmoothStep(double lo, double hi, double x) {
  const double t = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// The expected integral of one arc's darkening over the floor (m^2), for the
// uniform parameter ranges above: length x width integral x taper x strength.
double MeanArcDarkeningAreaM2() {
  const double length = 0.5 * (kMinLengthM + kMaxLengthM);
  const double width =
      2.0 * (kCoreFraction + 0.5 * (1.0 - kCoreFraction)) * 0.5 * (kMinHalfWidthM + kMaxHalfWidthM);
  const double taper = kTaperStart + 0.5 * (1.0 - kTaperStart);
  return length * width * taper * 0.5 * (kMinStrength + kMaxStrength);
}

}  // namespace

ScuffField::ScuffField(std::uint32_t seed, bool enabled) {
  if (!enabled) return;
  const double period = kPeriodM;
  cells_ = static_cast<int>(std::lround(period / kCellM));
  cell_entries_.assign(static_cast<std::size_t>(cells_) * cells_, {});
  const auto count = static_cast<std::int64_t>(
      std::lround(kMeanDarkening / MeanArcDarkeningAreaM2() * period * period));
  int draw = 0;
  std::int64_t index = 0;
  auto uniform = [&](double lo, double hi) {
    return lo + (hi - lo) * HashU32(index, draw++, seed + kScuffArcs) / 4294967296.0;
  };
  arcs_.reserve(static_cast<std::size_t>(count));
  for (; index < count; ++index) {
    draw = 0;
    const double mid_y = uniform(0.0, period);  // one draw per statement, y first
    const Vector2 mid(uniform(0.0, period), mid_y);
    const double heading = uniform(0.0, 2.0 * std::numbers::pi);
    const double radius = uniform(kMinRadiusM, kMaxRadiusM);
    const double turn = uniform(0.0, 1.0) < 0.5 ? 1.0 : -1.0;
    Arc arc;
    // The centre of curvature lies to the left (or right) of the heading.
    const Vector2 left(-std::sin(heading), std::cos(heading));
    arc.centre_m = mid + turn * radius * left;
    arc.mid_dir = (mid - arc.centre_m) / radius;
    arc.radius_m = radius;
    arc.half_angle_rad = 0.5 * uniform(kMinLengthM, kMaxLengthM) / radius;
    arc.cos_half_angle = std::cos(arc.half_angle_rad);
    arc.half_width_m = uniform(kMinHalfWidthM, kMaxHalfWidthM);
    arc.strength = static_cast<float>(uniform(kMinStrength, kMaxStrength));
    const auto a = static_cast<std::uint32_t>(arcs_.size());
    arcs_.push_back(arc);
    // Register the arc in every cell within its half width (plus the spacing
    // of the samples) of a sample every 5 cm along it.
    const double margin = arc.half_width_m + 0.03;
    const int samples = 1 + static_cast<int>(std::ceil(2.0 * arc.half_angle_rad * radius / 0.05));
    const double mid_angle = std::atan2(arc.mid_dir.y(), arc.mid_dir.x());
    for (int k = 0; k <= samples; ++k) {
      const double angle = mid_angle + arc.half_angle_rad * (2.0 * k / samples - 1.0);
      const Vector2 q = arc.centre_m + radius * Vector2(std::cos(angle), std::sin(angle));
      const auto x0 = static_cast<std::int64_t>(std::floor((q.x() - margin) / kCellM));
      const auto x1 = static_cast<std::int64_t>(std::floor((q.x() + margin) / kCellM));
      const auto y0 = static_cast<std::int64_t>(std::floor((q.y() - margin) / kCellM));
      const auto y1 = static_cast<std::int64_t>(std::floor((q.y() + margin) / kCellM));
      RegisterOnTile(a, x0, x1, y0, y1, cells_, &cell_entries_);
    }
  }
}

void RegisterOnTile(std::uint32_t a, std::int64_t x0, std::int64_t x1, std::int64_t y0,
                    std::int64_t y1, int cells,
                    std::vector<std::vector<std::uint32_t>>* cell_entries) {
  for (std::int64_t y = y0; y <= y1; ++y) {
    for (std::int64_t x = x0; x <= x1; ++x) {
      const std::int64_t sx = x >= 0 ? x / cells : -((-x + cells - 1) / cells);
      const std::int64_t sy = y >= 0 ? y / cells : -((-y + cells - 1) / cells);
      if (std::abs(sx) > 1 || std::abs(sy) > 1) continue;
      const std::size_t cell =
          static_cast<std::size_t>((y - sy * cells) * cells + (x - sx * cells));
      const auto entry = static_cast<std::uint32_t>(a * 9 + (sx + 1) + 3 * (sy + 1));
      std::vector<std::uint32_t>& list = (*cell_entries)[cell];
      if (list.empty() || list.back() != entry) list.push_back(entry);
    }
  }
}

float ScuffField::ArcDarkening(const Arc& arc, const Vector2& p_m) const {
  const Vector2 v = p_m - arc.centre_m;
  const double inner = arc.radius_m - arc.half_width_m, outer = arc.radius_m + arc.half_width_m;
  const double r2 = v.squaredNorm();
  if (r2 <= inner * inner || r2 >= outer * outer) return 0.0f;
  const double r = std::sqrt(r2);
  const Vector2 u = v / r;
  // Clearly beyond the arc's ends (the angle test below would fail) without
  // the arc tangent.
  if (arc.mid_dir.dot(u) < arc.cos_half_angle - 1e-9) return 0.0f;
  const double angle =
      std::atan2(arc.mid_dir.x() * u.y() - arc.mid_dir.y() * u.x(), arc.mid_dir.dot(u));
  const double t = std::abs(angle) / arc.half_angle_rad;
  if (t >= 1.0) return 0.0f;
  const double across = 1.0 - SmoothStep(kCoreFraction * arc.half_width_m, arc.half_width_m,
                                         std::abs(r - arc.radius_m));
  const double along = 1.0 - SmoothStep(kTaperStart, 1.0, t);
  return static_cast<float>(arc.strength * across * along);
}

float ScuffField::Darkening(const Vector2& p_m) const {
  if (cells_ == 0) return 0.0f;
  const double period = kPeriodM;
  const Vector2 wrapped(p_m.x() - period * std::floor(p_m.x() / period),
                        p_m.y() - period * std::floor(p_m.y() / period));
  const int cx = std::clamp(static_cast<int>(wrapped.x() / kCellM), 0, cells_ - 1);
  const int cy = std::clamp(static_cast<int>(wrapped.y() / kCellM), 0, cells_ - 1);
  float darkening = 0.0f;
  for (const std::uint32_t entry : cell_entries_[static_cast<std::size_t>(cy) * cells_ + cx]) {
    const int shift = static_cast<int>(entry % 9);
    const Vector2 q = wrapped + period * Vector2(shift % 3 - 1, shift / 3 - 1);
    darkening = std::max(darkening, ArcDarkening(arcs_[entry / 9], q));
  }
  return darkening;
}

}  // namespace groundline::sim::internal
