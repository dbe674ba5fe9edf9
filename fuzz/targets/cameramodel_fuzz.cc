// mrcal .cameramodel text (calibration/mrcal_cameramodel_io.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/mrcal_cameramodel_io.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto model = gcal::ParseMrcalCameraModel(gf::AsText(data, size), "fuzz.cameramodel");
  if (!model.ok()) gf::FuzzCheck(!model.message().empty(), "an error has a message");
  return 0;
}
