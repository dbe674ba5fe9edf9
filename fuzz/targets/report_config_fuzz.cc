// The report thresholds of a calibration config file (calibration/src/
// report_config.h): one section of each field type, as the report options
// read them.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "report_config.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  double max_rms_px = 0.5;
  double max_worst_px = 2.0;
  bool require_all_quadrants = true;
  int min_corners_per_quadrant = 4;
  const auto path = gf::WriteInput("calibration.yaml", data, size);
  const groundline::core::Status status =
      gcal::internal::ReadConfigSection(path, "intrinsics_report",
                                        {{"max_rms_px", &max_rms_px},
                                         {"max_worst_px", &max_worst_px},
                                         {"require_all_quadrants", &require_all_quadrants},
                                         {"min_corners_per_quadrant", &min_corners_per_quadrant}});
  if (!status.ok()) gf::FuzzCheck(!status.message().empty(), "an error has a message");
  return 0;
}
