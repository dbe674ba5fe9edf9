// ROS camera_info YAML (calibration/ros_camera_info_io.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/ros_camera_info_io.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto info = gcal::ParseRosCameraInfo(gf::AsText(data, size), "camera_info.yaml");
  if (!info.ok()) gf::FuzzCheck(!info.message().empty(), "an error has a message");
  return 0;
}
