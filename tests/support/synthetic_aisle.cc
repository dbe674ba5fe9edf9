#include "synthetic_aisle.h"

#include <Eigen/LU>
#include <cmath>

#include "groundline/calibration/mount_remap.h"
#include "groundline/core/angles.h"

namespace groundline::testing_aisle {

using calibration::RemapFloorPoint;
using core::kDegToRad;

CameraMount Moved(CameraMount m, double pitch_deg, double roll_deg, double height_mm,
                  double yaw_deg) {
  m.pitch_rad += pitch_deg * kDegToRad;
  m.roll_rad += roll_deg * kDegToRad;
  m.height_m += height_mm * 1e-3;
  m.yaw_rad += yaw_deg * kDegToRad;
  return m;
}

std::vector<WorldLine> Aisle(double length_m) {
  std::vector<WorldLine> lines = {{{-5.0, 0.6}, {length_m, 0.6}},
                                  {{-5.0, -0.6}, {length_m, -0.6}},
                                  {{-5.0, 0.08}, {length_m, 0.08}}};
  for (double x = 1.5; x < length_m; x += 3.0) lines.push_back({{x, -1.1}, {x, 1.1}});
  for (double x = 4.0; x < length_m; x += 9.0) {
    lines.push_back({{x, -0.6}, {x, 0.6}});
    lines.push_back({{x + 0.05, -0.6}, {x + 0.05, 0.6}});
  }
  return lines;
}

bool InView(const Eigen::Vector2d& p) {
  if (p.x() < 0.7 || p.x() > 2.2) return false;
  return std::abs(p.y()) < 0.35 + (p.x() - 0.7) * 0.43;
}

core::SE2 PoseAt(const Drive& d, double t) {
  const double w = 0.35;
  const double y = d.wobble_m * std::sin(w * t);
  const double heading = std::atan2(d.wobble_m * w * std::cos(w * t), d.speed_mps);
  return core::SE2(d.speed_mps * t, y, heading);
}

MountFrame MakeFrame(Drive& d, double t, const CameraMount& truth, const CameraMount& used) {
  MountFrame f;
  f.stamp_s = t;
  f.T_odom_base = PoseAt(d, t);
  f.mount_used = used;
  const core::SE2 T_base_world = f.T_odom_base.Inverse();
  std::normal_distribution<double> noise(0.0, d.sigma_m);
  auto add = [&](const Eigen::Vector2d& a_true, const Eigen::Vector2d& b_true) {
    Eigen::Vector2d a, b;
    if (!RemapFloorPoint(a_true, truth, used, &a) || !RemapFloorPoint(b_true, truth, used, &b))
      return;
    const Eigen::Vector2d dir = (b - a).normalized();
    const Eigen::Vector2d n(-dir.y(), dir.x());
    const double e1 = noise(d.rng), e2 = noise(d.rng);
    FloorSegment s;
    s.start_m = a + e1 * n;
    s.end_m = b + e2 * n;
    // (rho, alpha) from the two endpoints' distances d_i = t_i dalpha - drho.
    Eigen::Matrix2d J;
    J << -1.0, dir.dot(s.start_m), -1.0, dir.dot(s.end_m);
    const Eigen::Matrix2d Jinv = J.inverse();
    s.covariance = d.sigma_m * d.sigma_m * Jinv * Jinv.transpose();
    f.segments.push_back(s);
  };
  for (const WorldLine& l : d.world) {
    // The visible stretch of the line, sampled every 2 cm.
    const Eigen::Vector2d a = T_base_world * l.a, b = T_base_world * l.b;
    const int n = static_cast<int>((b - a).norm() / 0.02);
    int first = -1, last = -1;
    for (int i = 0; i <= n; ++i) {
      if (InView(a + (b - a) * i / n)) {
        if (first < 0) first = i;
        last = i;
      }
    }
    if (first < 0 || last - first < 10) continue;
    add(a + (b - a) * first / n, a + (b - a) * last / n);
  }
  std::uniform_real_distribution<double> ux(0.8, 2.1), uy(-0.6, 0.6), ua(-M_PI, M_PI), ul(0.3, 0.8);
  for (int i = 0; i < d.clutter_per_frame; ++i) {
    const Eigen::Vector2d c(ux(d.rng), uy(d.rng));
    const double angle = ua(d.rng), half = 0.5 * ul(d.rng);
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    FloorSegment s;
    s.start_m = c - half * dir;
    s.end_m = c + half * dir;
    s.covariance = Eigen::Vector2d(1e-6, 1e-5).asDiagonal();
    f.segments.push_back(s);
  }
  if (d.texture_points > 0 && d.previous && d.previous->stamp_s < t) {
    f.flow.previous_stamp_s = d.previous->stamp_s;
    f.flow.previous_mount = d.previous->used;
    const core::SE2 T_previous_base = d.previous->T_odom_base.Inverse() * f.T_odom_base;
    std::normal_distribution<double> texture_noise(0.0, d.texture_sigma_m);
    std::uniform_real_distribution<double> unit(0.0, 1.0), shift(-0.05, 0.05);
    for (int tries = 0; static_cast<int>(f.flow.points.size()) < d.texture_points && tries < 2000;
         ++tries) {
      const Eigen::Vector2d now(ux(d.rng), uy(d.rng));
      const Eigen::Vector2d then = T_previous_base * now;
      if (!InView(now) || !InView(then)) continue;
      Eigen::Vector2d seen_then, seen_now;
      if (!RemapFloorPoint(then, d.previous->truth, d.previous->used, &seen_then) ||
          !RemapFloorPoint(now, truth, used, &seen_now))
        continue;
      seen_then += Eigen::Vector2d(texture_noise(d.rng), texture_noise(d.rng));
      seen_now += Eigen::Vector2d(texture_noise(d.rng), texture_noise(d.rng));
      if (unit(d.rng) < d.texture_outlier_share) seen_now += Eigen::Vector2d(shift(d.rng), shift(d.rng));
      f.flow.points.emplace_back(seen_then, seen_now);
    }
  }
  d.previous = Drive::Previous{t, f.T_odom_base, truth, used};
  return f;
}

std::vector<MountFrame> Frames(Drive& d, double t0, double t1, const CameraMount& truth,
                               const CameraMount& used) {
  std::vector<MountFrame> frames;
  for (double t = t0; t < t1 - 1e-9; t += 1.0 / d.rate_hz)
    frames.push_back(MakeFrame(d, t, truth, used));
  return frames;
}

MountVector Difference(const CameraMount& a, const CameraMount& b) {
  return MountVector(a.pitch_rad - b.pitch_rad, a.roll_rad - b.roll_rad, a.height_m - b.height_m,
                     a.yaw_rad - b.yaw_rad);
}

}  // namespace groundline::testing_aisle
