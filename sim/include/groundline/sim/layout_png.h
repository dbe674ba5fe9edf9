// A top view of a World as a PNG, for eyes: the floor in concrete grey,
// obstacles in darker greys (rack beams above the LiDAR plane lighter), floor
// markings in their colours at their true width (joints as dark hairlines),
// moving obstacles at one instant (forklifts orange, pedestrians magenta), an
// optional trajectory in red with its start marked, the zone's name and a
// scale bar in metres. North (map +y) is up.
#ifndef GROUNDLINE_SIM_LAYOUT_PNG_H_
#define GROUNDLINE_SIM_LAYOUT_PNG_H_

#include <filesystem>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/sim/world.h"

namespace groundline::sim {

struct LayoutPngOptions {
  double pixels_per_m = 10.0;
  double margin_m = 3.0;
  double moving_obstacle_stamp_s = 0.0;
  int max_side_px = 16000;

  core::Status Validate() const;
};

// Writes the PNG atomically. `trajectory` (T_map_base) may be nullptr. Errors:
// invalid options, an image larger than max_side_px, a failed write.
core::Status WriteLayoutPng(const World& world, const core::Trajectory* trajectory,
                            const std::filesystem::path& path,
                            const LayoutPngOptions& options = LayoutPngOptions{});

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_LAYOUT_PNG_H_
