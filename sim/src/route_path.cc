// Smoothing a closed polyline into straights and clothoid-arc-clothoid turns,
// sampled densely with the curvature and a speed limit at every sample.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <vector>

#include "route_internal.h"

namespace groundline::sim::internal {
namespace {

// Heading (relative to the turn's start) at arc length u into a turn of the
// given shape and total angle (>= 0).
double TurnHeading(const TurnShape& shape, double angle_rad, double u) {
  const double lc = shape.clothoid_length_m;
  const double kp = shape.peak_curvature_1pm;
  const double total = shape.curve_length_m;
  if (lc > 0.0 && u <= lc) return kp * u * u / (2.0 * lc);
  if (u <= total - lc) return 0.5 * lc * kp + kp * (u - lc);
  const double r = total - u;
  return angle_rad - kp * r * r / (2.0 * lc);
}

double TurnCurvature(const TurnShape& shape, double u) {
  const double lc = shape.clothoid_length_m;
  const double kp = shape.peak_curvature_1pm;
  if (lc > 0.0 && u < lc) return kp * u / lc;
  if (lc > 0.0 && u > shape.curve_length_m - lc) return kp * (shape.curve_length_m - u) / lc;
  return kp;
}

// Displacement over [u0, u1] of a curve with heading h(u), by Simpson's rule.
template <typename Heading>
Vector2 Integrate(const Heading& h, double u0, double u1, int steps) {
  const double du = (u1 - u0) / steps;
  Vector2 sum = Vector2::Zero();
  for (int i = 0; i < steps; ++i) {
    const double a = u0 + i * du;
    for (const auto& [u, w] :
         {std::pair(a, 1.0), std::pair(a + 0.5 * du, 4.0), std::pair(a + du, 1.0)}) {
      sum += w * Vector2(std::cos(h(u)), std::sin(h(u)));
    }
  }
  return sum * (du / 6.0);
}

}  // namespace

TurnShape ComputeTurn(double angle_rad, double radius_m, double clothoid_length_m) {
  TurnShape shape;
  if (angle_rad < 1e-12) return shape;
  double kp = 1.0 / radius_m;
  if (clothoid_length_m > 0.0 && angle_rad < clothoid_length_m * kp) {
    kp = angle_rad / clothoid_length_m;
  }
  const double arc_angle = std::max(0.0, angle_rad - clothoid_length_m * kp);
  shape.clothoid_length_m = clothoid_length_m;
  shape.peak_curvature_1pm = kp;
  shape.curve_length_m = 2.0 * clothoid_length_m + arc_angle / kp;
  // By symmetry the corner lies on the normal at the turn's midpoint M, so the
  // tangent length is M.x + M.y tan(angle / 2) in the turn's start frame.
  const Vector2 mid = Integrate([&](double u) { return TurnHeading(shape, angle_rad, u); }, 0.0,
                                0.5 * shape.curve_length_m, 2000);
  shape.tangent_length_m = mid.x() + mid.y() * std::tan(0.5 * angle_rad);
  return shape;
}

core::Result<std::vector<PathSample>> SmoothLoop(const std::vector<Vector2>& polyline,
                                                 const RouteOptions& options,
                                                 std::mt19937_64* rng) {
  const std::size_t n = polyline.size() - 1;  // segments
  if (polyline.size() < 3 || (polyline.front() - polyline.back()).norm() > 1e-9) {
    return core::Status::Error("route: a loop needs a closed polyline of at least 2 segments");
  }
  std::vector<Vector2> dir(n);
  std::vector<double> seg_m(n), heading(n), cruise(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Vector2 d = polyline[j + 1] - polyline[j];
    seg_m[j] = d.norm();
    dir[j] = d / seg_m[j];
    heading[j] = std::atan2(d.y(), d.x());
    cruise[j] =
        std::uniform_real_distribution<double>(options.min_speed_mps, options.max_speed_mps)(*rng);
  }
  // The turn at each vertex, scaled down to fit half of each neighbouring straight.
  std::vector<TurnShape> turn(n);
  std::vector<double> signed_angle(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t in = (i + n - 1) % n;
    signed_angle[i] = core::WrapAngle(heading[i] - heading[in]);
    TurnShape t =
        ComputeTurn(std::abs(signed_angle[i]), options.turn_radius_m, options.transition_length_m);
    const double room_m = 0.5 * std::min(seg_m[in], seg_m[i]);
    if (t.tangent_length_m > room_m) {
      const double scale = room_m / t.tangent_length_m;
      if (options.turn_radius_m * scale < options.min_turn_radius_m) {
        std::ostringstream message;
        message << "route: the turn at (" << polyline[i].x() << ", " << polyline[i].y()
                << ") m needs a radius of " << options.turn_radius_m * scale
                << " m to fit, below min_turn_radius_m = " << options.min_turn_radius_m;
        return core::Status::Error(message.str());
      }
      t.tangent_length_m *= scale;
      t.curve_length_m *= scale;
      t.clothoid_length_m *= scale;
      t.peak_curvature_1pm /= scale;
    }
    turn[i] = t;
  }

  std::vector<PathSample> samples;
  double s_m = 0.0;
  double yaw = heading[0];
  auto speed_limit_in_turn = [&](double curvature) {
    const double v = std::abs(curvature) > 0.0
                         ? std::sqrt(options.max_lateral_accel_mps2 / std::abs(curvature))
                         : options.max_speed_mps;
    return std::clamp(v, options.min_speed_mps, options.max_speed_mps);
  };
  auto add_line = [&](const Vector2& a, const Vector2& b, std::size_t seg) {
    const double len = (b - a).norm();
    for (double u = 0.0; u < len; u += kPathStepM) {
      const Vector2 p = a + u * dir[seg];
      samples.push_back({s_m + u, p.x(), p.y(), yaw, 0.0, cruise[seg]});
    }
    s_m += len;
  };
  auto add_turn = [&](std::size_t i) {
    const TurnShape& t = turn[i];
    const double angle = std::abs(signed_angle[i]);
    const double sign = signed_angle[i] >= 0.0 ? 1.0 : -1.0;
    const std::size_t in = (i + n - 1) % n;
    Vector2 p = polyline[i] - t.tangent_length_m * dir[in];
    const double yaw0 = yaw;
    auto h = [&](double u) { return yaw0 + sign * TurnHeading(t, angle, u); };
    double u = 0.0;
    while (u < t.curve_length_m) {
      const double k = sign * TurnCurvature(t, u);
      samples.push_back({s_m + u, p.x(), p.y(), h(u), k, speed_limit_in_turn(k)});
      const double u_next = std::min(u + kPathStepM, t.curve_length_m);
      p += Integrate(h, u, u_next, 4);
      u = u_next;
    }
    s_m += t.curve_length_m;
    yaw = yaw0 + signed_angle[i];
    [[maybe_unused]] const Vector2 end = polyline[i] + t.tangent_length_m * dir[i];
    assert((p - end).norm() < 1e-6);
  };

  const Vector2 start = 0.5 * (polyline[0] + polyline[1]);
  add_line(start, polyline[1] - turn[1 % n].tangent_length_m * dir[0], 0);
  for (std::size_t k = 1; k <= n; ++k) {
    const std::size_t i = k % n;
    add_turn(i);
    const Vector2 a = polyline[i] + turn[i].tangent_length_m * dir[i];
    const Vector2 b =
        k < n ? Vector2(polyline[k + 1] - turn[(k + 1) % n].tangent_length_m * dir[i]) : start;
    add_line(a, b, i);
  }
  samples.push_back({s_m, start.x(), start.y(), yaw, 0.0, cruise[0]});
  return samples;
}

std::vector<PathSample> OpenPath(const std::vector<PathSample>& loop, double start_m,
                                 double length_m) {
  assert(loop.size() >= 2 && loop.back().s_m > 0.0 && length_m > 0.0);
  const double lap_m = loop.back().s_m;
  const double lap_yaw_rad = loop.back().yaw_rad - loop.front().yaw_rad;
  std::size_t first = 0;
  while (first + 2 < loop.size() && loop[first].s_m < start_m) ++first;
  const double offset_m = loop[first].s_m;
  std::vector<PathSample> out;
  for (int lap = 0;; ++lap) {
    for (std::size_t i = lap == 0 ? first : 1; i < loop.size(); ++i) {
      PathSample p = loop[i];
      p.s_m += lap * lap_m - offset_m;
      p.yaw_rad += lap * lap_yaw_rad;
      if (p.s_m >= length_m) {
        const PathSample& a = out.back();
        const double f = (length_m - a.s_m) / (p.s_m - a.s_m);
        auto lerp = [f](double x, double y) { return x + f * (y - x); };
        out.push_back({length_m, lerp(a.x_m, p.x_m), lerp(a.y_m, p.y_m), lerp(a.yaw_rad, p.yaw_rad),
                       lerp(a.curvature_1pm, p.curvature_1pm),
                       lerp(a.speed_limit_mps, p.speed_limit_mps)});
        return out;
      }
      out.push_back(p);
    }
  }
}

void AddTrackingDeviation(const RouteOptions& options, std::vector<PathSample>* loop) {
  if (options.tracking_deviation_m <= 0.0 || loop->size() < 2) return;
  const double length_m = loop->back().s_m;
  const auto k_min =
      static_cast<int>(std::max(1.0, std::ceil(length_m / options.tracking_wavelength_max_m)));
  const auto k_max =
      std::max(k_min, static_cast<int>(length_m / options.tracking_wavelength_min_m));
  // Its own stream: the planner's draws (and so the route) stay those of the seed.
  std::mt19937_64 rng(options.seed ^ 0x7261636b696e67ULL);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * std::numbers::pi);
  const double amplitude_scale =
      options.tracking_deviation_m * std::sqrt(2.0 / static_cast<double>(k_max - k_min + 1));
  struct Wave {
    double amplitude_m, wavenumber_1pm, phase_rad;
  };
  std::vector<Wave> waves;
  for (int k = k_min; k <= k_max; ++k) {
    waves.push_back(
        {amplitude_scale * gauss(rng), 2.0 * std::numbers::pi * k / length_m, phase(rng)});
  }
  double previous_s_m = 0.0, previous_stretch = 1.0, new_s_m = 0.0;
  for (std::size_t i = 0; i < loop->size(); ++i) {
    PathSample& p = (*loop)[i];
    double d = 0.0, d1 = 0.0, d2 = 0.0;  // d(s) and its first two derivatives
    for (const Wave& w : waves) {
      const double arg = w.wavenumber_1pm * p.s_m + w.phase_rad;
      const double sn = std::sin(arg), cs = std::cos(arg);
      d += w.amplitude_m * sn;
      d1 += w.amplitude_m * w.wavenumber_1pm * cs;
      d2 -= w.amplitude_m * w.wavenumber_1pm * w.wavenumber_1pm * sn;
    }
    // Offset curve q = p + d n: q' = (1 - kappa d) t + d' n. Its heading turns
    // by atan2(d', 1 - kappa d); the curvature (per its own arc length) follows
    // from the derivative of that angle. The ramp of kappa along clothoids is
    // left out of it: the term d' kappa' d is below 1e-4 1/m.
    const double a = 1.0 - p.curvature_1pm * d, b = d1;
    const double a1 = -p.curvature_1pm * d1, b1 = d2;
    const double stretch = std::hypot(a, b);
    p.x_m -= d * std::sin(p.yaw_rad);
    p.y_m += d * std::cos(p.yaw_rad);
    p.yaw_rad += std::atan2(b, a);
    p.curvature_1pm = (p.curvature_1pm + (a * b1 - b * a1) / (stretch * stretch)) / stretch;
    if (i > 0) new_s_m += 0.5 * (previous_stretch + stretch) * (p.s_m - previous_s_m);
    previous_s_m = p.s_m;
    previous_stretch = stretch;
    p.s_m = new_s_m;
  }
}

}  // namespace groundline::sim::internal
