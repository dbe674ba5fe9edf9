// wheel_encoders.csv (core/dataset_records.h: ReadWheelEncoders).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/core/dataset_records.h"

namespace gc = groundline::core;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto readings = gc::ReadWheelEncoders(gf::WriteInput("wheel_encoders.csv", data, size));
  if (!readings.ok()) gf::FuzzCheck(!readings.message().empty(), "an error has a message");
  return 0;
}
