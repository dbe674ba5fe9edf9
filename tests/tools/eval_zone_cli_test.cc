// `groundline eval --dataset DIR --zone Z --run LABEL=DIR`: the per-zone table
// of issue 6 on a short simulated zone B drive (no camera, no LiDAR): the
// aisle exits come from the dataset's floor map, the NEES from the run's
// covariance side file, and a ground truth shifted by a known offset gives
// that offset as ATE and as the error at every aisle exit.
#include <gtest/gtest.h>

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
using testing::RunGroundline;

class EvalZoneCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::groundline::testing::ScratchDir("eval_zone");
    dataset_ = dir_ / "zone_b";
    std::string out;
    // 100 m from seed 3 drive up the rest of an 85 m aisle and out of it.
    ASSERT_EQ(RunGroundline("sim --zone B --length 100m --seed 3 --no-lidar --no-camera --out " +
                                Quoted(dataset_),
                            dir_, &out),
              0)
        << out;
  }
  std::filesystem::path dir_;
  std::filesystem::path dataset_;
};

TEST_F(EvalZoneCli, ShiftedTruthGivesItsOffsetEverywhereAndOdometryHasNees) {
  // Ground truth moved 3 cm along map x and 4 cm along y: 5 cm everywhere.
  const core::Result<core::Trajectory> truth =
      core::ReadTumTrajectory(dataset_ / "ground_truth.tum");
  ASSERT_TRUE(truth.ok()) << truth.message();
  core::Trajectory shifted;
  for (std::size_t i = 0; i < truth->size(); i += 10) {
    core::StampedPose p = (*truth)[i];
    p.pose = core::SE2(p.pose.x() + 0.03, p.pose.y() + 0.04, p.pose.yaw());
    shifted.push_back(p);
  }
  std::filesystem::create_directories(dir_ / "shifted");
  ASSERT_TRUE(core::WriteTumTrajectory(dir_ / "shifted" / "trajectory.tum", shifted).ok());
  std::string out;
  const std::filesystem::path odometry = dir_ / "odometry";
  ASSERT_EQ(RunGroundline("localize --dataset " + Quoted(dataset_) + " --out " + Quoted(odometry),
                          dir_, &out),
            0)
      << out;
  ASSERT_TRUE(std::filesystem::exists(odometry / "trajectory_covariance.txt"));

  const std::filesystem::path json = dir_ / "eval.json";
  ASSERT_EQ(RunGroundline("eval --dataset " + Quoted(dataset_) + " --zone B --run odometry=" +
                              Quoted(odometry) + " --run shifted=" + Quoted(dir_ / "shifted") +
                              " --json " + Quoted(json),
                          dir_, &out),
            0)
      << out;
  EXPECT_NE(out.find("zone B"), std::string::npos) << out;
  EXPECT_NE(out.find("missed: ate_rmse"), std::string::npos) << out;
  std::ifstream in(json);
  const nlohmann::json runs = nlohmann::json::parse(in);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0]["label"], "odometry");
  EXPECT_GT(runs[0]["nees_n"].get<int>(), 100);
  const nlohmann::json& s = runs[1];
  EXPECT_EQ(s["label"], "shifted");
  EXPECT_NEAR(s["ate_rmse_m"].get<double>(), 0.05, 1e-6);
  EXPECT_GE(s["aisle_exits_n"].get<int>(), 1);
  EXPECT_EQ(s["aisle_exits_unmatched"].get<int>(), 0);
  // The estimate (10 Hz) interpolated at the exit: within 1 mm on a curve.
  EXPECT_NEAR(s["aisle_exit_max_m"].get<double>(), 0.05, 1e-3);
  EXPECT_FALSE(s.contains("nees_n"));  // no covariance file: no NEES
}

TEST(EvalZoneCliUsage, MalformedRunIsAUsageError) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("eval_zone_usage");
  std::string out;
  EXPECT_EQ(RunGroundline("eval --dataset x --run nolabel", dir, &out), 2) << out;
  EXPECT_NE(out.find("LABEL=DIR"), std::string::npos) << out;
  EXPECT_EQ(RunGroundline("eval --dataset x --run a=b --est c.tum", dir, &out), 2) << out;
}

}  // namespace
}  // namespace groundline
