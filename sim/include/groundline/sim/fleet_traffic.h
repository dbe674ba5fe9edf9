// Traffic between the robots of a simulated fleet. Routes are planned one
// robot at a time, each blind to the others, so two of them would drive
// through each other: in a LiDAR whose sensor is inside the other robot's
// body every return is that body, data no site can produce. A fleet
// manager keeps its vehicles apart; this is the simulator's stand-in for
// one, by priority: robot 0 drives as planned and robot k yields to robots
// 0..k-1, whose retimed trajectories are fixed before it.
//
// Yielding (YieldToOthers) retimes a route without changing its path: the
// vehicle passes through the same poses in the same order, waiting where it
// must. It is safe-interval path planning (Phillips and Likhachev 2011) on
// the route's one path:
//  1. the path is cut into stations every station_spacing_m; a station is
//     occupied while another robot is within separation_m of it (a robot is
//     present from its first to its last stamp: after its route it has
//     driven off to its dock), padded by pad_s on both sides for the time a
//     stop and a start take; the rest of the time are its safe intervals;
//  2. the earliest schedule is found station by station (forward only):
//     driving from one station to the next at the planned speed, waiting at a
//     station only within one of its safe intervals, leaving it before the
//     interval ends;
//  3. the schedule's waits become smooth stops: the vehicle follows the
//     planned timeline at a rate in [0, 1] (so speeds, yaw rates and the
//     odometry derived from the poses stay those of a real vehicle), braking
//     at max_brake_mps2 to stop at a station it must wait at and speeding up
//     again at max_accel_mps2 once the wait is over.
// SimulateFleet checks the result (MinimumSeparation) and fails naming the
// robots, the time and the distance if two bodies would still overlap.
#ifndef GROUNDLINE_SIM_FLEET_TRAFFIC_H_
#define GROUNDLINE_SIM_FLEET_TRAFFIC_H_

#include <vector>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/sim/route.h"

namespace groundline::sim {

struct TrafficOptions {
  // Between base_links; two 1.7 x 0.92 m bodies touch at 1.93 m at most.
  double separation_m = 2.5;
  double station_spacing_m = 0.25;
  double pad_s = 4.0;           // a stop from 2 m/s at 1 m/s^2 and a start at 0.5 m/s^2 cost ~3 s
  double max_accel_mps2 = 0.5;  // the route's (RouteOptions::max_accel_mps2)
  double max_brake_mps2 = 1.0;
  double max_total_wait_s = 1800.0;  // no schedule within this: an error

  core::Status Validate() const;
};

// The route retimed so that it keeps clear of `others` (see above). The
// result has the route's sample period, starts at its first stamp and ends
// at its last pose; speed_mps and yaw_rate_radps are scaled alike.
// Errors: invalid options, a route with fewer than two samples, a start
// where another robot passes, or no schedule within max_total_wait_s.
core::Result<Route> YieldToOthers(const Route& route,
                                  const std::vector<const core::Trajectory*>& others,
                                  const TrafficOptions& options);

struct Separation {
  double distance_m = 0.0;  // smallest base_link distance while both are present
  double stamp_s = 0.0;     // when
};
// Sampled at every stamp of `a` within b's span (b interpolated).
Separation MinimumSeparation(const core::Trajectory& a, const core::Trajectory& b);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_FLEET_TRAFFIC_H_
