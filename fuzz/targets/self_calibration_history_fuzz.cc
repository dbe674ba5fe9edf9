// A run's health.jsonl as `calibrate history` reads it
// (calibration/self_calibration_history.h). An accepted history has finite
// values, non-negative sigmas and non-negative window and step counts; the
// comparison with a truth and the page take it whole.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_input.h"
#include "groundline/calibration/self_calibration_history.h"

namespace gcal = groundline::calibration;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto history =
      gcal::ReadSelfCalibrationHistory(gf::WriteInput("health.jsonl", data, size));
  if (!history.ok()) {
    gf::FuzzCheck(!history.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(!history->empty(), "an accepted history has a sample");
  for (const gcal::SelfCalibrationSample& s : *history) {
    gf::FuzzCheck(std::isfinite(s.stamp_s) && s.value.allFinite() && s.sigma.allFinite() &&
                      (s.sigma.array() >= 0.0).all() && s.windows >= 0 && s.steps >= 0,
                  "an accepted sample is finite, its sigmas and counts non-negative");
  }
  const std::vector<groundline::core::CameraExtrinsicsRecord> truth = {
      {0.0, 0.58, 0.74, 0.0, 0.0, 0.42, 0.0}};
  const gcal::SelfCalibrationErrors e = gcal::CompareWithTruth(*history, truth);
  gf::FuzzCheck(e.samples >= 0 && e.samples <= static_cast<int>(history->size()),
                "the errors count the samples");
  gf::FuzzCheck(!gcal::SelfCalibrationHistoryHtml(*history, &truth, "fuzz").empty(),
                "an accepted history is drawn");
  return 0;
}
