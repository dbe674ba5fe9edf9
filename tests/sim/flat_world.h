// An empty 100 m x 100 m floor (no markings, joints or racks) for the camera
// renderer tests to paint on.
#ifndef GROUNDLINE_TESTS_SIM_FLAT_WORLD_H_
#define GROUNDLINE_TESTS_SIM_FLAT_WORLD_H_

#include "groundline/sim/world.h"

namespace groundline::testing {

inline sim::World FlatWorld() {
  sim::World world;
  world.name = "flat";
  world.floor_min_m = sim::Vector2(-50, -50);
  world.floor_max_m = sim::Vector2(50, 50);
  return world;
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_SIM_FLAT_WORLD_H_
