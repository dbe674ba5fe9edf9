// The demo's flow end to end through the executable: simulate a short run,
// check the dataset, replay it, and read the run outputs of EVAL.md; and the
// errors a user gets for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"
#include "groundline/core/trajectory_io.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::Quoted;
using testing::ReadJson;
using testing::RunGroundline;

class CliFlow : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::groundline::testing::ScratchDir("flow");
    dataset_ = dir_ / "zone_c";
    std::string out;
    // Zone C with a 150 m route is a short preset route; no LiDAR and no camera
    // keep it small (both streams have their own tests).
    ASSERT_EQ(RunGroundline("sim --zone C --length 150m --seed 3 --no-lidar --no-camera --out " +
                                Quoted(dataset_),
                            dir_, &out),
              0)
        << out;
  }
  std::filesystem::path dir_;
  std::filesystem::path dataset_;
};

TEST_F(CliFlow, SimulateCheckLocalizeEvaluate) {
  std::string out;
  ASSERT_EQ(RunGroundline("dataset check " + Quoted(dataset_), dir_, &out), 0) << out;
  EXPECT_NE(out.find("dataset OK"), std::string::npos) << out;
  EXPECT_TRUE(std::filesystem::exists(dataset_ / "layout.png"));

  const std::filesystem::path run = dir_ / "run";
  ASSERT_EQ(
      RunGroundline("localize --dataset " + Quoted(dataset_) + " --out " + Quoted(run), dir_, &out),
      0)
      << out;
  for (const char* file :
       {"trajectory.tum", "trajectory_odometry_rate.tum", "health.jsonl", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(run / file)) << file;
  }
  const nlohmann::json summary = ReadJson(run / "summary.json");
  const core::Result<core::Trajectory> keyframes = core::ReadTumTrajectory(run / "trajectory.tum");
  ASSERT_TRUE(keyframes.ok()) << keyframes.message();
  EXPECT_EQ(summary["n_keyframes"].get<std::size_t>(), keyframes->size());
  // A 150 m route at one keyframe per 0.20 m (or 5 deg), taken at the first
  // 100 Hz sample beyond it (up to 2 cm later), gives at least 680 keyframes.
  EXPECT_GE(keyframes->size(), 680u);
  // Dead reckoning with the simulator's wheel errors drifts, but stays bounded
  // on 150 m: well above a centimetre, well below the loop's size.
  const double ate = summary["accuracy"]["ate_rmse_m"].get<double>();
  EXPECT_GT(ate, 0.01);
  EXPECT_LT(ate, 30.0);

  // The same figure from the eval command, which reads the files back.
  const std::filesystem::path json = dir_ / "eval.json";
  ASSERT_EQ(RunGroundline("eval --est " + Quoted(run / "trajectory.tum") + " --ref " +
                              Quoted(dataset_ / "ground_truth.tum") + " --json " + Quoted(json),
                          dir_, &out),
            0)
      << out;
  EXPECT_NEAR(ReadJson(json)["ate_rmse_m"].get<double>(), ate, 1e-6);
}

TEST_F(CliFlow, CorruptDatasetIsReportedWithFileAndLine) {
  {
    std::ofstream append(dataset_ / "wheel_encoders.csv", std::ios::app);
    append << "1.0,0.1,nan\n";
  }
  std::string out;
  EXPECT_EQ(RunGroundline("dataset check " + Quoted(dataset_), dir_, &out), 1) << out;
  EXPECT_NE(out.find("wheel_encoders.csv:"), std::string::npos) << out;
  EXPECT_EQ(
      RunGroundline("localize --dataset " + Quoted(dataset_) + " --out " + Quoted(dir_ / "run"),
                    dir_, &out),
      1)
      << out;
  EXPECT_NE(out.find("wheel_encoders.csv:"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "run" / "summary.json"));
}

TEST(CliUsage, BadFlagsAreUsageErrors) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("usage");
  std::string out;
  EXPECT_EQ(RunGroundline("sim --zone Q --out " + Quoted(dir / "x"), dir, &out), 2) << out;
  EXPECT_NE(out.find("--zone"), std::string::npos) << out;
  EXPECT_EQ(RunGroundline("sim --length -3m --out " + Quoted(dir / "x"), dir, &out), 2) << out;
  EXPECT_EQ(RunGroundline("no-such-command", dir, &out), 2) << out;
  EXPECT_EQ(RunGroundline("--version", dir, &out), 0) << out;
  EXPECT_NE(out.find("groundline "), std::string::npos) << out;
}

}  // namespace
}  // namespace groundline
