// floor_map.yaml (core/floor_map.h). An accepted map passes Validate() and
// survives the writer's exact round trip with the same markings.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/core/floor_map.h"

namespace gc = groundline::core;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto map = gc::ReadFloorMap(gf::WriteInput("floor_map.yaml", data, size));
  if (!map.ok()) {
    gf::FuzzCheck(!map.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(map->Validate().ok(), "an accepted floor map passes Validate()");
  const auto path = gf::ScratchDir() / "floor_map_again.yaml";
  gf::FuzzCheck(gc::WriteFloorMap(path, *map).ok(), "an accepted floor map can be written");
  const auto again = gc::ReadFloorMap(path);
  gf::FuzzCheck(
      again.ok() && again->markings.size() == map->markings.size() && again->frame == map->frame,
      "a written floor map reads back");
  for (std::size_t i = 0; again.ok() && i < map->markings.size(); ++i) {
    gf::FuzzCheck(again->markings[i].polyline_m == map->markings[i].polyline_m,
                  "polylines read back exactly");
  }
  return 0;
}
