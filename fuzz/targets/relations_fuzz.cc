// Kuemmerle relation files (io/relations.h: ReadRelations).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/io/relations.h"

namespace gf = groundline::fuzz;
namespace gio = groundline::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto relations = gio::ReadRelations(gf::WriteInput("log.relations", data, size));
  if (!relations.ok()) gf::FuzzCheck(!relations.message().empty(), "an error has a message");
  return 0;
}
