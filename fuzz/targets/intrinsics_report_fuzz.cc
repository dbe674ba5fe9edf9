// The intrinsics report that `calibrate floor --intrinsics-report` folds in,
// report.json (calibration/floor_calibration.h: ReadIntrinsicsReportSummary).
// An accepted summary has covariance maps of cells_x * cells_y cells in
// ascending range.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/floor_calibration.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto report = gcal::ReadIntrinsicsReportSummary(gf::WriteInput("report.json", data, size));
  if (!report.ok()) {
    gf::FuzzCheck(!report.message().empty(), "an error has a message");
    return 0;
  }
  for (std::size_t i = 0; i < report->covariance_maps.size(); ++i) {
    const auto& map = report->covariance_maps[i];
    gf::FuzzCheck(map.cells_x >= 1 && map.cells_y >= 1 &&
                      map.covariance_px2.size() ==
                          static_cast<std::size_t>(map.cells_x) * static_cast<std::size_t>(map.cells_y),
                  "a covariance map has cells_x * cells_y cells");
    gf::FuzzCheck(i == 0 || report->covariance_maps[i - 1].range_m <= map.range_m,
                  "covariance maps in ascending range");
  }
  return 0;
}
