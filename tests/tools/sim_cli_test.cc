// `groundline sim --scenario` end to end through the executable: a tiny run
// with a knock, flags overriding the file, and a bad scenario's message.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.h"
#include "groundline/core/dataset.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::Quoted;
using testing::RunGroundline;

constexpr char kTinyScenario[] = R"(format: groundline-sim-scenario
version: 1.0
zone: C
seed: 2
route: {length_m: 40}
lidar: {enabled: false}
camera:
  rate_hz: 0.25
  width_px: 320
  height_px: 256
  focal_px: 283
perturbations:
  steps:
    - {cause: knock, at_s: 10, yaw_deg: 1.5, roll_deg: 0.5}
)";

TEST(SimCli, ScenarioRunWithFlagOverrides) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("sim_cli");
  const std::filesystem::path scenario = dir / "tiny.yaml";
  std::ofstream(scenario) << kTinyScenario;
  const std::filesystem::path out = dir / "run";
  std::string output;
  ASSERT_EQ(RunGroundline("sim --scenario " + Quoted(scenario) + " --seed 5 --length 30m --out " +
                              Quoted(out),
                          dir, &output),
            0)
      << output;
  const core::Result<core::Dataset> d = core::ReadDataset(out);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_EQ(d->manifest.provenance.at("seed"), "5");  // the flag won
  EXPECT_EQ(d->manifest.provenance.at("zone"), "C");  // from the file
  EXPECT_FALSE(d->manifest.lidar.has_value());        // from the file
  ASSERT_TRUE(d->manifest.camera.has_value());
  EXPECT_EQ(d->manifest.camera->image_width_px, 320);
  EXPECT_EQ(d->manifest.camera->rate_hz, 0.25);
  double travelled_m = 0.0;
  for (std::size_t k = 1; k < d->ground_truth.size(); ++k) {
    travelled_m +=
        (d->ground_truth[k].pose.translation() - d->ground_truth[k - 1].pose.translation()).norm();
  }
  EXPECT_NEAR(travelled_m, 30.0, 0.3);  // --length 30m, not the file's 40 m
  // The knock at 10 s: the true mount changes once.
  ASSERT_EQ(d->ground_truth_extrinsics.size(), 2u);
  EXPECT_NEAR(d->ground_truth_extrinsics[1].stamp_s - d->ground_truth.front().stamp_s, 10.0, 0.011);
  EXPECT_NEAR(d->ground_truth_extrinsics[1].yaw_rad, 1.5 * 3.14159265358979 / 180.0, 1e-9);
  EXPECT_GE(d->images.size(), 4u);
}

TEST(SimCli, FleetScenarioWritesOneDatasetPerRobot) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("sim_cli_fleet");
  const std::filesystem::path scenario = dir / "fleet.yaml";
  std::ofstream(scenario) << "format: groundline-sim-scenario\nversion: 1.0\nzone: D\n"
                             "robots: 2\nroute: {length_m: 30}\ncamera: {enabled: false}\n"
                             "lidar: {rate_hz: 2}\n";
  std::string output;
  ASSERT_EQ(RunGroundline("sim --scenario " + Quoted(scenario) + " --out " + Quoted(dir / "out"),
                          dir, &output),
            0)
      << output;
  for (const char* robot : {"robot_0", "robot_1"}) {
    const core::Result<core::Dataset> d = core::ReadDataset(dir / "out" / robot);
    ASSERT_TRUE(d.ok()) << d.message();
    EXPECT_EQ(d->manifest.provenance.at("robots"), "2");
    EXPECT_FALSE(d->scans.empty());
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / robot / "layout.png"));
  }
}

TEST(SimCli, BadScenarioNamesFileLineAndField) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("sim_cli_bad");
  const std::filesystem::path scenario = dir / "bad.yaml";
  std::ofstream(scenario) << "format: groundline-sim-scenario\nversion: 1.0\nroute:\n"
                             "  max_speed_mps: fast\n";
  std::string output;
  EXPECT_EQ(RunGroundline("sim --scenario " + Quoted(scenario) + " --out " + Quoted(dir / "x"), dir,
                          &output),
            1);
  EXPECT_NE(output.find(scenario.string() + ":4: field 'route.max_speed_mps'"), std::string::npos)
      << output;
}

}  // namespace
}  // namespace groundline
