// Floor tag layout YAML (calibration/tag_layout.h). An accepted layout
// passes TagLayout::Validate().
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/tag_layout.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto layout = gcal::ParseTagLayoutYaml(gf::AsText(data, size), "tag_layout.yaml");
  if (!layout.ok()) {
    gf::FuzzCheck(!layout.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(layout->Validate().ok(), "an accepted layout passes Validate()");
  return 0;
}
