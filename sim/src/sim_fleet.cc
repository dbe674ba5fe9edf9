// SimulateFleet (sim_run.h): several robots in one world, each seeing the
// others in its LiDAR, kept apart by yielding (fleet_traffic.h).
#include <memory>
#include <string>
#include <vector>

#include "groundline/sim/sim_run.h"
#include "options_check.h"
#include "sim_run_internal.h"

namespace groundline::sim {
namespace {

// Robot k > 0 gets its seed from this stream of the run seed (plus k).
constexpr std::uint64_t kRobotStreamBase = 1000;

}  // namespace

core::Status FleetOptions::Validate() const {
  constexpr const char* kOwner = "FleetOptions";
  return internal::FirstError({
      internal::CheckRange(kOwner, "robots", robots, 1, 64),
      internal::CheckRange(kOwner, "robot_half_extent_m.x", robot_half_extent_m.x(), 0.05, 5.0),
      internal::CheckRange(kOwner, "robot_half_extent_m.y", robot_half_extent_m.y(), 0.05, 5.0),
      internal::CheckRange(kOwner, "robot_height_m", robot_height_m, 0.05, 10.0),
      internal::CheckRange(kOwner, "robot_reflectivity", robot_reflectivity, 0.0, 1.0),
      traffic.Validate(),
  });
}

core::Result<std::vector<SimRun>> SimulateFleet(const SimRunOptions& options,
                                                const FleetOptions& fleet,
                                                const SimProgress& progress) {
  if (core::Status s = options.Validate(); !s.ok()) return s.WithContext("sim options");
  if (core::Status s = fleet.Validate(); !s.ok()) return s.WithContext("fleet options");
  if (progress) progress("zone", 0.0);
  core::Result<World> world = internal::BuildRunZone(options);
  if (!world.ok()) return world.status().WithContext("building the zone");
  if (progress) progress("zone", 1.0);

  const auto n = static_cast<std::size_t>(fleet.robots);
  std::vector<std::uint64_t> seeds(n, options.seed);
  std::vector<Route> routes;
  std::vector<std::shared_ptr<const core::Trajectory>> truths;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) seeds[k] = internal::StreamSeed(options.seed, kRobotStreamBase + k);
    if (progress) progress("route", static_cast<double>(k) / static_cast<double>(n));
    core::Result<Route> route = internal::PlanRobotRoute(*world, options, seeds[k]);
    if (!route.ok()) return route.status().WithContext("robot " + std::to_string(k));
    if (k > 0) {
      std::vector<const core::Trajectory*> before;
      for (const auto& truth : truths) before.push_back(truth.get());
      TrafficOptions traffic = fleet.traffic;
      traffic.max_accel_mps2 = options.route.max_accel_mps2;
      route = YieldToOthers(*route, before, traffic);
      if (!route.ok()) return route.status().WithContext("robot " + std::to_string(k));
      // Priority yielding can leave a robot waiting where one before it
      // later drives through: two bodies in one place is no data.
      const double overlap_m = 2.0 * fleet.robot_half_extent_m.norm();
      for (std::size_t j = 0; j < k; ++j) {
        const Separation closest = MinimumSeparation(route->T_map_base, *truths[j]);
        if (closest.distance_m < overlap_m) {
          return core::Status::Error("robots " + std::to_string(j) + " and " + std::to_string(k) +
                                     " come within " + std::to_string(closest.distance_m) +
                                     " m of each other at " + std::to_string(closest.stamp_s) +
                                     " s (their bodies overlap below " + std::to_string(overlap_m) +
                                     " m): yielding could not keep them apart; try another seed");
        }
      }
    }
    routes.push_back(std::move(route).value());
    truths.push_back(std::make_shared<const core::Trajectory>(routes.back().T_map_base));
  }
  if (progress) progress("route", 1.0);

  std::vector<SimRun> runs;
  for (std::size_t k = 0; k < n; ++k) {
    World seen = *world;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == k) continue;
      MovingObstacle other;
      other.kind = MovingKind::kRobot;
      other.half_extent_m = fleet.robot_half_extent_m;
      other.z_min_m = 0.0;
      other.z_max_m = fleet.robot_height_m;
      other.reflectivity = fleet.robot_reflectivity;
      other.trajectory = truths[j];
      other.leaves_after_trajectory = true;  // driven off to its dock
      seen.moving.push_back(std::move(other));
    }
    const SimProgress robot_progress = [&](std::string_view stage, double fraction) {
      if (progress) progress("robot " + std::to_string(k) + " " + std::string(stage), fraction);
    };
    core::Result<SimRun> run =
        internal::SimulateRobot(std::move(seen), routes[k], options, seeds[k], robot_progress);
    if (!run.ok()) return run.status().WithContext("robot " + std::to_string(k));
    core::DatasetManifest& m = run->dataset.manifest;
    m.name += "_robot" + std::to_string(k);
    m.description += ", robot " + std::to_string(k) + " of " + std::to_string(n);
    m.provenance["robot"] = std::to_string(k);
    m.provenance["robots"] = std::to_string(n);
    m.provenance["robot_seed"] = std::to_string(seeds[k]);
    runs.push_back(std::move(run).value());
  }
  return runs;
}

}  // namespace groundline::sim
