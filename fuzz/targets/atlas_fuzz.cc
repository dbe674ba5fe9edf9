// atlas.json (localization/atlas.h). An accepted atlas passes Validate() and
// the writer takes it back.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/localization/atlas.h"

namespace gf = groundline::fuzz;
namespace gl = groundline::localization;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto atlas = gl::ReadAtlas(gf::WriteInput("atlas.json", data, size));
  if (!atlas.ok()) {
    gf::FuzzCheck(!atlas.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(atlas->Validate().ok(), "an accepted atlas passes Validate()");
  const auto path = gf::ScratchDir() / "atlas_again.json";
  gf::FuzzCheck(gl::WriteAtlas(path, *atlas).ok(), "an accepted atlas can be written");
  const auto again = gl::ReadAtlas(path);
  gf::FuzzCheck(again.ok() && again->lines.size() == atlas->lines.size() &&
                    again->junctions.size() == atlas->junctions.size(),
                "a written atlas reads back");
  return 0;
}
