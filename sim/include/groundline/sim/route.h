// Ground-truth trajectories along a zone's natural paths (its RoadGraph),
// driven smoothly at warehouse speeds: an open route of exactly length_m
// (default), or a closed loop that returns to its start (closed_loop).
//
// How a route is made:
// 1. A seeded random walk over the road graph (no U-turns, no turn sharper than
//    max_turn_angle_rad, edges weighted by their preference and by how rarely
//    they were used) is closed back to its start by the shortest admissible
//    path; of many walk prefixes the one whose closed loop is nearest the
//    requested length is kept (several walks are tried).
//    Zone B thus traverses aisles end to end and hops across in the
//    cross-aisles; zone D circulates along the corridors; A and C loop between
//    the staging blocks and the docks.
// 2. Every corner becomes a symmetric clothoid-arc-clothoid turn (curvature
//    ramps linearly over transition_length_m, so yaw rate and wheel speeds are
//    continuous), with arc radius turn_radius_m, scaled down (never below
//    min_turn_radius_m) when the neighbouring straights are short.
// 3. Speed: each straight gets a cruise speed drawn in [min_speed_mps,
//    max_speed_mps]; turns are limited by max_lateral_accel_mps2 (but never
//    below min_speed_mps); transitions respect max_accel_mps2. The loop is
//    periodic: the speed and pose at the end equal those at the start, which
//    is on a straight (the middle of the first graph edge).
// 3b. The vehicle follows the path with a small, smooth sideways deviation
//    (tracking_deviation_m), the same on every lap.
// 4. The path is checked against the static obstacles (all heights): the
//    vehicle, a disc of vehicle_half_width_m around base_link, must keep
//    min_clearance_m. A violation is an error, not a silently bad route.
//
// 5. Length. A closed loop is the planned loop itself: its length is the
//    nearest the road graph allows (within length_tolerance_fraction, else an
//    error; zone B's loops come in steps of a few metres, zone D's corridor
//    ring only in laps of ~250 m). An open route (closed_loop = false) starts
//    at a seeded point of the planned loop, drives it lap after lap and stops
//    exactly at length_m (so any length >= 1 m in any zone); it starts and
//    ends at rest, accelerating and braking at max_accel_mps2.
//
// The result is T_map_base (base_link: midpoint of the drive axle) sampled at
// sample_rate_hz: over one loop, t in [0, duration_s) for a closed loop; over
// t in [0, duration_s] for an open route (the last sample is its end).
#ifndef GROUNDLINE_SIM_ROUTE_H_
#define GROUNDLINE_SIM_ROUTE_H_

#include <cstdint>
#include <numbers>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/sim/world.h"

namespace groundline::sim {

struct RouteOptions {
  std::uint64_t seed = 1;
  double length_m = 1200.0;
  // false: an open route of exactly length_m; true: a closed loop (below).
  bool closed_loop = false;
  // Closed loops: accept a loop whose length differs from length_m by at most
  // this fraction.
  double length_tolerance_fraction = 0.01;
  int max_walk_attempts = 512;

  double min_speed_mps = 1.0;
  double max_speed_mps = 2.0;
  double max_lateral_accel_mps2 = 0.8;
  double max_accel_mps2 = 0.5;

  double turn_radius_m = 2.0;
  double min_turn_radius_m = 1.0;
  double transition_length_m = 0.8;
  double max_turn_angle_rad = 100.0 * std::numbers::pi / 180.0;

  double vehicle_half_width_m = 0.46;
  double min_clearance_m = 0.3;

  double sample_rate_hz = 100.0;
  double start_stamp_s = 0.0;

  // Path following: a real vehicle does not drive the planned path exactly.
  // The driven path is offset sideways by a smooth random d(s) (standard
  // deviation tracking_deviation_m, wavelengths in [min, max]); the heading
  // follows the offset path (0.015 m over 8-40 m: heading deviations of
  // 0.4 deg rms, curvature 0.005 1/m rms). 0: the planned path exactly, which lines the vehicle up
  // with the floor markings to the micrometre, so that every lane line sits at the same sub-cell
  // phase of the camera's bird's-eye grid in every frame.
  double tracking_deviation_m = 0.015;
  double tracking_wavelength_min_m = 8.0;
  double tracking_wavelength_max_m = 40.0;

  core::Status Validate() const;
};

struct Route {
  core::Trajectory T_map_base;  // at sample_rate_hz (see the file comment)
  bool closed_loop = false;
  // Per sample of T_map_base: forward speed and yaw rate (curvature * speed).
  std::vector<double> speed_mps;
  std::vector<double> yaw_rate_radps;
  // The road-graph polyline of the (planned) loop; closed (first == last).
  // An open route drives it from the middle of its first segment, lap after lap.
  std::vector<Vector2> waypoints_m;
  double length_m = 0.0;    // arc length of the smooth path
  double duration_s = 0.0;  // time to drive it
  double max_curvature_1pm = 0.0;
  // Smallest distance between the vehicle disc and a static obstacle.
  double min_clearance_m = 0.0;
};

// Errors: invalid options, a world without roads, no loop within the length
// tolerance, a turn that does not fit, or a path that violates the clearance.
core::Result<Route> GenerateRoute(const World& world, const RouteOptions& options);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_ROUTE_H_
