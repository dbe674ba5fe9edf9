// ground_truth_extrinsics.csv (core/dataset_records.h: ReadGroundTruthExtrinsics).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/core/dataset_records.h"

namespace gc = groundline::core;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto records =
      gc::ReadGroundTruthExtrinsics(gf::WriteInput("ground_truth_extrinsics.csv", data, size));
  if (!records.ok()) gf::FuzzCheck(!records.message().empty(), "an error has a message");
  return 0;
}
