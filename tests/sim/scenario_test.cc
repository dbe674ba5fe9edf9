// Scenario files: the shipped samples load; each kind of mistake is reported
// with the file, the line and the field.
#include "groundline/sim/scenario.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "test_data.h"
#include "test_units.h"

namespace groundline::sim {
namespace {

namespace fs = std::filesystem;
using ::groundline::testing::kDeg;

fs::path Write(const std::string& name, const std::string& text) {
  const fs::path path = ::groundline::testing::ScratchDir("scenario") / name;
  std::ofstream(path) << text;
  return path;
}

TEST(Scenario, ShippedSamplesLoad) {
  int n = 0;
  for (const auto& entry : fs::directory_iterator(GROUNDLINE_SAMPLE_SCENARIOS_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    const core::Result<Scenario> s = LoadScenario(entry.path());
    EXPECT_TRUE(s.ok()) << s.message();
    ++n;
  }
  EXPECT_GE(n, 3);
}

TEST(Scenario, EveryKindOfKeyReachesItsOption) {
  const fs::path path = Write("full.yaml", R"(format: groundline-sim-scenario
version: 1.0
zone: b
seed: 9
robots: 1
layout: {num_aisles: 6, pallet_fill: 0.5}
route: {length_m: 250, closed_loop: true, max_speed_mps: 1.5, max_turn_angle_deg: 95}
encoders: {slip_rate_per_m: 0, ticks_per_revolution: 2048}
lidar: {enabled: false, range_max_m: 20}
camera:
  rate_hz: 4
  mount: {height_m: 0.6, pitch_deg: 40, yaw_deg: 0.5}
nuisances:
  shadows: {enabled: true, cover: 0.5}
  noise: {enabled: false}
  randomized: {enabled: true}
  glare: {row_pitch_m: 0.3, row_length_m: 2}
  cast_shadows: {enabled: true, factor: 0.45, penumbra_m: 0.02}
  vehicle_shadow: {enabled: true, luminaire_height_m: 9}
  tire_marks: {enabled: true, density_per_100m2: 2.5}
  patches: {enabled: true, contrast: 0.2}
  wet: {enabled: true, glare_gain: 1.5}
  standing_objects: {enabled: true, clutter_per_100m: 6}
perturbations:
  height_loss_mm_per_km: 3
  steps:
    - {cause: payload, at_s: 10, pitch_deg: 0.5, height_mm: -2}
survey_noise: {marking_vertex_sigma_m: 0.004, face_offset_sigma_m: 0.03, face_angle_deg: 0.1}
)");
  const core::Result<Scenario> s = LoadScenario(path);
  ASSERT_TRUE(s.ok()) << s.message();
  const SimRunOptions& o = s->options;
  EXPECT_EQ(o.zone, Zone::kB);
  EXPECT_EQ(o.seed, 9u);
  EXPECT_EQ(o.zone_b.num_aisles, 6);
  EXPECT_EQ(o.survey_noise.marking_vertex_sigma_m, 0.004);
  EXPECT_EQ(o.survey_noise.face_offset_sigma_m, 0.03);
  EXPECT_NEAR(o.survey_noise.face_angle_sigma_rad, 0.1 * kDeg, 1e-15);
  EXPECT_EQ(o.zone_b.pallet_fill, 0.5);
  EXPECT_EQ(o.route.length_m, 250.0);
  EXPECT_TRUE(o.route.closed_loop);
  EXPECT_NEAR(o.route.max_turn_angle_rad, 95 * kDeg, 1e-12);
  EXPECT_EQ(o.encoders.ticks_per_revolution, 2048);
  EXPECT_FALSE(o.with_lidar);
  EXPECT_EQ(o.camera_rate_hz, 4.0);
  EXPECT_NEAR(o.camera.mount.pitch_rad, 40 * kDeg, 1e-12);
  EXPECT_NEAR(o.camera.mount.yaw_rad, 0.5 * kDeg, 1e-12);
  EXPECT_TRUE(o.render.shadows);
  EXPECT_EQ(o.render.shadow_cover, 0.5);
  EXPECT_FALSE(o.render.noise);
  EXPECT_TRUE(o.render.glare);  // untouched default
  EXPECT_TRUE(o.randomize_nuisances);
  EXPECT_EQ(o.render.glare_row_pitch_m, 0.3);
  EXPECT_EQ(o.render.glare_row_length_m, 2.0);
  EXPECT_TRUE(o.render.cast_shadows);
  EXPECT_EQ(o.render.cast_shadow_factor, 0.45);
  EXPECT_EQ(o.render.shadow_penumbra_m, 0.02);
  EXPECT_TRUE(o.render.vehicle_shadow);
  EXPECT_EQ(o.render.luminaire_height_m, 9.0);
  EXPECT_TRUE(o.render.tire_marks);
  EXPECT_EQ(o.render.tire_mark_density, 2.5);
  EXPECT_TRUE(o.render.patches);
  EXPECT_EQ(o.render.patch_contrast, 0.2);
  EXPECT_TRUE(o.render.wet);
  EXPECT_EQ(o.render.wet_glare_gain, 1.5);
  EXPECT_TRUE(o.render.standing_objects);
  EXPECT_EQ(o.render.clutter_per_100m, 6.0);
  EXPECT_NEAR(o.mount_perturbations.height_loss_m_per_km, 0.003, 1e-15);
  ASSERT_EQ(o.mount_perturbations.steps.size(), 1u);
  EXPECT_EQ(o.mount_perturbations.steps[0].cause, "payload");
  EXPECT_NEAR(o.mount_perturbations.steps[0].pitch_rad, 0.5 * kDeg, 1e-12);
  EXPECT_NEAR(o.mount_perturbations.steps[0].height_m, -0.002, 1e-15);
}

struct Bad {
  std::string name;
  std::string body;    // after the format and version lines
  std::string expect;  // substring of the message (after "file:line: ")
  int line;            // 0: no line expected (a range check by Validate)
};
void PrintTo(const Bad& b, std::ostream* os) { *os << b.name; }

class BadScenario : public ::testing::TestWithParam<Bad> {};

TEST_P(BadScenario, NamesTheFileAndTheField) {
  const Bad& bad = GetParam();
  const fs::path path =
      Write(bad.name + ".yaml", "format: groundline-sim-scenario\nversion: 1.0\n" + bad.body);
  const core::Result<Scenario> s = LoadScenario(path);
  ASSERT_FALSE(s.ok());
  const std::string where = path.string() + (bad.line > 0 ? ":" + std::to_string(bad.line) : "");
  EXPECT_EQ(s.message().rfind(where, 0), 0u) << s.message();
  EXPECT_NE(s.message().find(bad.expect), std::string::npos) << s.message();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadScenario,
    ::testing::Values(
        Bad{"typo", "route:\n  lenght_m: 5\n", "field 'route.lenght_m'", 4},
        Bad{"not_a_number", "route:\n  max_speed_mps: fast\n", "field 'route.max_speed_mps'", 4},
        Bad{"bad_bool", "camera: {enabled: yes please}\n", "field 'camera.enabled'", 3},
        Bad{"bad_zone", "zone: E\n", "field 'zone'", 3},
        Bad{"layout_of_another_zone", "zone: D\nlayout: {num_aisles: 4}\n",
            "field 'layout.num_aisles'", 4},
        Bad{"unknown_nuisance", "nuisances:\n  fog: {enabled: true}\n", "field 'nuisances.fog'", 4},
        Bad{"step_without_time", "perturbations:\n  steps:\n    - {cause: knock, yaw_deg: 1}\n",
            "field 'perturbations.steps[0].at_s'", 5},
        Bad{"unknown_cause", "perturbations:\n  steps:\n    - {cause: rain, at_s: 1}\n",
            "field 'perturbations.steps[0].cause'", 5},
        Bad{"no_robots", "robots: 0\n", "field 'robots'", 3},
        Bad{"out_of_range", "route: {max_speed_mps: 50}\n", "RouteOptions.max_speed_mps", 0}),
    [](const ::testing::TestParamInfo<Bad>& info) { return info.param.name; });

TEST(Scenario, WrongFormatNameIsRefused) {
  const fs::path path = Write("format.yaml", "format: groundline-dataset\nversion: 1.0\n");
  const core::Result<Scenario> s = LoadScenario(path);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("groundline-sim-scenario"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace groundline::sim
