// The simulated commissioning scene of the floor-calibration tests; a scene
// that cannot be built fails the calling test.
#ifndef GROUNDLINE_TESTS_CALIBRATION_COMMISSIONING_FIXTURE_H_
#define GROUNDLINE_TESTS_CALIBRATION_COMMISSIONING_FIXTURE_H_

#include <gtest/gtest.h>

#include <utility>

#include "groundline/sim/commissioning_scene.h"

namespace groundline::testing {

inline sim::CommissioningScene CommissioningSceneOrFail(const sim::CommissioningOptions& options) {
  core::Result<sim::CommissioningScene> scene = sim::MakeCommissioningScene(options);
  EXPECT_TRUE(scene.ok()) << scene.message();
  return std::move(scene).value();
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_CALIBRATION_COMMISSIONING_FIXTURE_H_
