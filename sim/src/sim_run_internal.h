// The stages of a simulated run (sim_run.h), shared by SimulateRun and
// SimulateFleet.
#ifndef GROUNDLINE_SIM_SRC_SIM_RUN_INTERNAL_H_
#define GROUNDLINE_SIM_SRC_SIM_RUN_INTERNAL_H_

#include <cstdint>

#include "groundline/sim/sim_run.h"

namespace groundline::sim::internal {

// splitmix64 of (seed, stream): independent seeds for a run's random streams.
std::uint64_t StreamSeed(std::uint64_t seed, std::uint64_t stream);

// The zone of options.zone with its layout options, seeded by options.seed.
core::Result<World> BuildRunZone(const SimRunOptions& options);

// A robot's route; robot_seed seeds it (and the robot's other streams).
core::Result<Route> PlanRobotRoute(const World& world, const SimRunOptions& options,
                                   std::uint64_t robot_seed);

// The robot's encoders, LiDAR (seeing `world`, moving obstacles included) and
// camera plan along `route`, as a SimRun with its dataset. Options must be valid.
core::Result<SimRun> SimulateRobot(World world, Route route, const SimRunOptions& options,
                                   std::uint64_t robot_seed, const SimProgress& progress);

}  // namespace groundline::sim::internal

#endif  // GROUNDLINE_SIM_SRC_SIM_RUN_INTERNAL_H_
