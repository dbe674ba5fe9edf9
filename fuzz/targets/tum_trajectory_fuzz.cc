// TUM trajectories (core/trajectory_io.h: ReadTumTrajectory), and the
// covariance side file read onto an accepted one (trajectory_covariance_io.h).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_input.h"
#include "groundline/core/trajectory_covariance_io.h"
#include "groundline/core/trajectory_io.h"

namespace gc = groundline::core;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto trajectory = gc::ReadTumTrajectory(gf::WriteInput("trajectory.tum", data, size));
  if (!trajectory.ok()) {
    gf::FuzzCheck(!trajectory.message().empty(), "an error has a message");
    return 0;
  }
  // The same bytes as a covariance file: each stamp then matches its own pose.
  gc::Trajectory with_covariances = *trajectory;
  const gc::Status attached = gc::AttachTrajectoryCovariances(
      gf::WriteInput("trajectory.cov", data, size), &with_covariances);
  gf::FuzzCheck(attached.ok() || !attached.message().empty(), "an error has a message");
  return 0;
}
