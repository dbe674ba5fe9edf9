// Ground homography YAML (calibration/ground_homography.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/ground_homography.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto h = gcal::ParseGroundHomographyYaml(gf::AsText(data, size), "homography.yaml");
  if (!h.ok()) gf::FuzzCheck(!h.message().empty(), "an error has a message");
  return 0;
}
