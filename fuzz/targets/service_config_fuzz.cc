// The service's config, serve.yaml (service/service_config.h). An accepted
// config passes Validate().
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/service/service_config.h"

namespace gs = groundline::service;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto config = gs::ReadServiceConfig(gf::WriteInput("serve.yaml", data, size));
  if (!config.ok()) {
    gf::FuzzCheck(!config.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(config->Validate().ok(), "an accepted config passes Validate()");
  return 0;
}
