// EuRoC ground-truth CSV (core/trajectory_io.h: ReadEurocTrajectory).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/core/trajectory_io.h"

namespace gc = groundline::core;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto trajectory = gc::ReadEurocTrajectory(gf::WriteInput("data.csv", data, size));
  if (!trajectory.ok()) gf::FuzzCheck(!trajectory.message().empty(), "an error has a message");
  return 0;
}
