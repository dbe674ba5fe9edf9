// Camera mount (extrinsics) YAML (calibration/camera_mount_yaml.h). An
// accepted mount passes CameraMount::Validate().
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/camera_mount_yaml.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto mount = gcal::ParseCameraMountYaml(gf::AsText(data, size), "extrinsics.yaml");
  if (!mount.ok()) {
    gf::FuzzCheck(!mount.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(mount->Validate().ok(), "an accepted mount passes Validate()");
  return 0;
}
