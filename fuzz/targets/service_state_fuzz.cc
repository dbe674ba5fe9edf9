// The service's saved state, state.json (service/service_state.h): what a
// restart reads back from disk. An accepted state is written and reads back
// exactly.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/service/service_state.h"

namespace gs = groundline::service;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto state = gs::ReadServiceState(gf::WriteInput("state.json", data, size));
  if (!state.ok()) {
    gf::FuzzCheck(!state.message().empty(), "an error has a message");
    return 0;
  }
  const auto path = gf::ScratchDir() / "state_again.json";
  gf::FuzzCheck(gs::WriteServiceState(path, *state).ok(), "an accepted state can be written");
  const auto again = gs::ReadServiceState(path);
  gf::FuzzCheck(again.ok() && again->stamp_s == state->stamp_s &&
                    again->T_map_base.x() == state->T_map_base.x() &&
                    again->T_map_base.yaw() == state->T_map_base.yaw() &&
                    again->covariance == state->covariance,
                "a written state reads back exactly");
  return 0;
}
