// bev_uncertainty.json (calibration/bev_uncertainty.h). An accepted map has
// cells_x * cells_y cells, at least one known, every known one symmetric
// with non-negative eigenvalues; the writer takes it back and it reads back
// the same.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/calibration/bev_uncertainty.h"
#include "groundline/core/atomic_file.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto map = gcal::ReadBevUncertaintyMap(gf::WriteInput("bev_uncertainty.json", data, size));
  if (!map.ok()) {
    gf::FuzzCheck(!map.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(map->covariance_m2.size() ==
                    static_cast<std::size_t>(map->cells_x) * static_cast<std::size_t>(map->cells_y),
                "the cells fill the grid");
  gf::FuzzCheck(map->KnownCells() > 0, "an accepted map knows a cell");
  for (const Eigen::Matrix2d& c : map->covariance_m2) {
    gf::FuzzCheck(!c.allFinite() || (c(0, 1) == c(1, 0) && c(0, 0) >= 0.0 && c(1, 1) >= 0.0 &&
                                      c.determinant() >= -1e-9 * c(0, 0) * c(1, 1)),
                  "a known cell is a covariance");
  }
  const auto path = gf::ScratchDir() / "bev_uncertainty_again.json";
  gf::FuzzCheck(groundline::core::WriteFileAtomically(path, gcal::BevUncertaintyJson(*map)).ok(),
                "an accepted map can be written");
  const auto again = gcal::ReadBevUncertaintyMap(path);
  gf::FuzzCheck(again.ok() && again->cells_x == map->cells_x && again->cells_y == map->cells_y &&
                    again->KnownCells() == map->KnownCells(),
                "a written map reads back");
  return 0;
}
