// images/index.csv (core/dataset_records.h: ReadImageIndex), without the
// existence check of the image files (it would reject nearly every input).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/core/dataset_records.h"

namespace gc = groundline::core;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto images =
      gc::ReadImageIndex(gf::WriteInput("index.csv", data, size), /*check_files=*/false);
  if (!images.ok()) gf::FuzzCheck(!images.message().empty(), "an error has a message");
  return 0;
}
