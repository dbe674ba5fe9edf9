// OpenCV calibration YAML (calibration/opencv_calibration_io.h), read through
// cv::FileStorage from a file as the tools do.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/opencv_calibration_io.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto camera = gcal::ReadOpenCvCalibration(gf::WriteInput("camera.yaml", data, size));
  if (!camera.ok()) gf::FuzzCheck(!camera.message().empty(), "an error has a message");
  return 0;
}
