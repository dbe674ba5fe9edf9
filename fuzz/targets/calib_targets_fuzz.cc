// Calibration target definitions, targets.yaml (calibration/calib_target.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/calib_target.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto targets = gcal::ParseCalibTargets(gf::AsText(data, size), "targets.yaml");
  if (!targets.ok()) gf::FuzzCheck(!targets.message().empty(), "an error has a message");
  return 0;
}
