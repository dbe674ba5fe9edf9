// Private pieces of the route generator (see route.h): turn geometry, the
// loop planner on the road graph, and the dense smooth path.
#ifndef GROUNDLINE_SIM_SRC_ROUTE_INTERNAL_H_
#define GROUNDLINE_SIM_SRC_ROUTE_INTERNAL_H_

#include <random>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/sim/route.h"
#include "groundline/sim/world.h"

namespace groundline::sim::internal {

// A symmetric clothoid-arc-clothoid turn by angle_rad (>= 0): curvature ramps
// from 0 to peak over the clothoid length, stays at peak on the arc, ramps
// down. For turns smaller than clothoid_length / radius there is no arc and
// the peak curvature is lower. tangent_length_m is the distance from the
// corner of the two straights to where the turn starts (and ends).
struct TurnShape {
  double tangent_length_m = 0.0;
  double curve_length_m = 0.0;
  double clothoid_length_m = 0.0;
  double peak_curvature_1pm = 0.0;
};
TurnShape ComputeTurn(double angle_rad, double radius_m, double clothoid_length_m);

// Road-graph node indices of a closed loop (first == last) whose smoothed
// length is as near options.length_m as the walks found; an error when the
// nearest differs from it by more than tolerance_m (infinity: any loop). The
// search stops at the first loop within good_enough_m of the length (a large
// value keeps the seed's first walk, so that seeds give different routes).
core::Result<std::vector<int>> PlanLoop(const RoadGraph& roads, const RouteOptions& options,
                                        double tolerance_m, double good_enough_m,
                                        std::mt19937_64* rng);

// The smooth loop through a closed polyline, densely sampled (about every
// kPathStepM of arc length, and at every element boundary). The first sample is
// at the middle of the first polyline segment; the last sample closes the loop
// (same position as the first, yaw unwrapped by the total turn).
struct PathSample {
  double s_m = 0.0;
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;  // unwrapped along the path
  double curvature_1pm = 0.0;
  double speed_limit_mps = 0.0;
};
inline constexpr double kPathStepM = 0.01;
core::Result<std::vector<PathSample>> SmoothLoop(const std::vector<Vector2>& closed_polyline_m,
                                                 const RouteOptions& options, std::mt19937_64* rng);

// Path-following deviation (RouteOptions::tracking_deviation_m): the loop
// offset sideways by d(s) = sum_k a_k sin(2 pi k s / L + phi_k), L the loop
// length, k over the wavelengths L / k in [tracking_wavelength_min_m,
// tracking_wavelength_max_m], a_k Gaussian with E[d^2] = tracking_deviation_m^2
// (seeded by options.seed, its own stream). The heading turns with the offset
// curve (the vehicle still drives where it points), the curvature and the arc
// length are those of the offset curve. Periodic in s, so the loop still closes.
// No-op for tracking_deviation_m == 0.
void AddTrackingDeviation(const RouteOptions& options, std::vector<PathSample>* loop);

// An open path of exactly length_m: the loop driven from its first sample at
// or beyond arc length start_m (in [0, loop length)), lap after lap (arc
// length and yaw continued), cut at length_m (the last sample interpolated).
std::vector<PathSample> OpenPath(const std::vector<PathSample>& loop, double start_m,
                                 double length_m);

}  // namespace groundline::sim::internal

#endif  // GROUNDLINE_SIM_SRC_ROUTE_INTERNAL_H_
