// Simulation scenario YAML (sim/scenario.h: LoadScenario).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/sim/scenario.h"

namespace gf = groundline::fuzz;
namespace gs = groundline::sim;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto scenario = gs::LoadScenario(gf::WriteInput("scenario.yaml", data, size));
  if (!scenario.ok()) {
    gf::FuzzCheck(!scenario.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(scenario->options.Validate().ok() && scenario->robots >= 1,
                "an accepted scenario passes SimRunOptions::Validate()");
  return 0;
}
