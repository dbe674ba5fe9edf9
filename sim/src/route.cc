#include "groundline/sim/route.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "groundline/sim/obstacle_index.h"
#include "options_check.h"
#include "route_internal.h"

namespace groundline::sim {
namespace {

using internal::CheckRange;
using internal::PathSample;

constexpr const char* kRouteOwner = "RouteOptions";
constexpr double kClearanceCheckStepM = 0.05;

// Speed profile: the speed limits, reduced so that speeding up and slowing
// down respect max_accel_mps2. A closed loop is periodic (the last sample is
// the first one again); an open route starts and ends at rest.
std::vector<double> SpeedProfile(const std::vector<PathSample>& path, double max_accel_mps2,
                                 bool periodic) {
  const std::size_t n = path.size();
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = path[i].speed_limit_mps;
  const auto tie_ends = [&] {
    if (periodic) {
      v[0] = v[n - 1] = std::min(v[0], v[n - 1]);
    } else {
      v[0] = v[n - 1] = 0.0;
    }
  };
  tie_ends();
  auto reachable = [&](double from_v, std::size_t a, std::size_t b) {
    return std::sqrt(from_v * from_v + 2.0 * max_accel_mps2 * std::abs(path[b].s_m - path[a].s_m));
  };
  for (int round = 0; round < 2; ++round) {
    for (std::size_t i = 1; i < n; ++i) v[i] = std::min(v[i], reachable(v[i - 1], i - 1, i));
    tie_ends();
  }
  for (int round = 0; round < 2; ++round) {
    for (std::size_t i = n - 1; i-- > 0;) v[i] = std::min(v[i], reachable(v[i + 1], i + 1, i));
    tie_ends();
  }
  return v;
}

}  // namespace

core::Status RouteOptions::Validate() const {
  return internal::FirstError({
      CheckRange(kRouteOwner, "length_m", length_m, 1.0, 1e6),
      CheckRange(kRouteOwner, "length_tolerance_fraction", length_tolerance_fraction, 1e-4, 1.0),
      CheckRange(kRouteOwner, "max_walk_attempts", max_walk_attempts, 1, 100000),
      CheckRange(kRouteOwner, "min_speed_mps", min_speed_mps, 0.05, 10.0),
      CheckRange(kRouteOwner, "max_speed_mps", max_speed_mps, min_speed_mps, 10.0),
      CheckRange(kRouteOwner, "max_lateral_accel_mps2", max_lateral_accel_mps2, 0.01, 10.0),
      CheckRange(kRouteOwner, "max_accel_mps2", max_accel_mps2, 0.01, 10.0),
      CheckRange(kRouteOwner, "min_turn_radius_m", min_turn_radius_m, 0.1, 100.0),
      CheckRange(kRouteOwner, "turn_radius_m", turn_radius_m, min_turn_radius_m, 100.0),
      CheckRange(kRouteOwner, "transition_length_m", transition_length_m, 0.0,
                 10.0 * turn_radius_m),
      CheckRange(kRouteOwner, "max_turn_angle_rad", max_turn_angle_rad, 0.1, 2.7),
      CheckRange(kRouteOwner, "vehicle_half_width_m", vehicle_half_width_m, 0.0, 5.0),
      CheckRange(kRouteOwner, "min_clearance_m", min_clearance_m, 0.0, 5.0),
      CheckRange(kRouteOwner, "sample_rate_hz", sample_rate_hz, 0.1, 10000.0),
      CheckRange(kRouteOwner, "tracking_deviation_m", tracking_deviation_m, 0.0, 0.1),
      CheckRange(kRouteOwner, "tracking_wavelength_min_m", tracking_wavelength_min_m, 1.0, 1000.0),
      CheckRange(kRouteOwner, "tracking_wavelength_max_m", tracking_wavelength_max_m,
                 tracking_wavelength_min_m, 10000.0),
  });
}

core::Result<Route> GenerateRoute(const World& world, const RouteOptions& o) {
  if (core::Status status = o.Validate(); !status.ok()) return status;
  std::mt19937_64 rng(o.seed);
  // A closed loop searches for the nearest length; an open route is cut to
  // length anyway, so the first walk within a quarter of it will do (and
  // different seeds keep different starts and walks).
  const double tolerance_m = o.closed_loop ? o.length_tolerance_fraction * o.length_m
                                           : std::numeric_limits<double>::infinity();
  const double good_enough_m = o.closed_loop ? 0.5 * tolerance_m : 0.25 * o.length_m;
  core::Result<std::vector<int>> nodes =
      internal::PlanLoop(world.roads, o, tolerance_m, good_enough_m, &rng);
  if (!nodes.ok()) return nodes.status().WithContext(world.name);
  Route route;
  for (int node : *nodes) route.waypoints_m.push_back(world.roads.nodes_m[std::size_t(node)]);
  core::Result<std::vector<PathSample>> smoothed = internal::SmoothLoop(route.waypoints_m, o, &rng);
  if (!smoothed.ok()) return smoothed.status().WithContext(world.name);
  internal::AddTrackingDeviation(o, &*smoothed);
  // An open route starts anywhere along the loop (seeded).
  const double start_m = std::uniform_real_distribution<double>(0.0, smoothed->back().s_m)(rng);
  const std::vector<PathSample> path = o.closed_loop
                                           ? std::move(smoothed).value()
                                           : internal::OpenPath(*smoothed, start_m, o.length_m);
  route.closed_loop = o.closed_loop;
  route.length_m = path.back().s_m;

  // Clearance of the vehicle disc from every static obstacle, at any height.
  const ObstacleIndex index(world, ObstacleIndex::Options{});
  const double search_m = o.vehicle_half_width_m + o.min_clearance_m + 1.0;
  route.min_clearance_m = std::numeric_limits<double>::infinity();
  double next_check_m = 0.0;
  for (const PathSample& p : path) {
    route.max_curvature_1pm = std::max(route.max_curvature_1pm, std::abs(p.curvature_1pm));
    if (p.s_m < next_check_m) continue;
    next_check_m = p.s_m + kClearanceCheckStepM;
    const double clearance_m = index.ClearanceM({p.x_m, p.y_m}, search_m) - o.vehicle_half_width_m;
    route.min_clearance_m = std::min(route.min_clearance_m, clearance_m);
    if (clearance_m < o.min_clearance_m) {
      std::ostringstream message;
      message << world.name << ": route: at (" << p.x_m << ", " << p.y_m << ") m the vehicle is "
              << clearance_m
              << " m from an obstacle, less than min_clearance_m = " << o.min_clearance_m
              << "; the road graph passes too close to an obstacle";
      return core::Status::Error(message.str());
    }
  }

  // Time along the path, then uniform sampling.
  const std::vector<double> v = SpeedProfile(path, o.max_accel_mps2, o.closed_loop);
  std::vector<double> t(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i) {
    t[i] = t[i - 1] + 2.0 * (path[i].s_m - path[i - 1].s_m) / (v[i - 1] + v[i]);
  }
  route.duration_s = t.back();
  std::size_t i = 0;
  for (std::size_t k = 0;; ++k) {
    const double tk = static_cast<double>(k) / o.sample_rate_hz;
    // A loop's last sample would repeat its first; an open route ends there.
    if (o.closed_loop ? tk >= route.duration_s : tk > route.duration_s + 1e-9) break;
    while (i + 2 < path.size() && t[i + 1] <= tk) ++i;
    const double f = std::clamp((tk - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0);
    const PathSample& a = path[i];
    const PathSample& b = path[i + 1];
    auto lerp = [f](double x, double y) { return x + f * (y - x); };
    const double speed = lerp(v[i], v[i + 1]);
    route.T_map_base.push_back(
        {o.start_stamp_s + tk,
         core::SE2(lerp(a.x_m, b.x_m), lerp(a.y_m, b.y_m), lerp(a.yaw_rad, b.yaw_rad)),
         std::nullopt});
    route.speed_mps.push_back(speed);
    route.yaw_rate_radps.push_back(speed * lerp(a.curvature_1pm, b.curvature_1pm));
  }
  return route;
}

}  // namespace groundline::sim
