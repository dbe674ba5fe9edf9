// Runs `groundline eval` as a user would and checks its exit codes and the
// JSON contract of EVAL.md.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

#include "cli_runner.h"
#include "groundline/core/trajectory_io.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::ReadJson;

// Runs `groundline eval` with `args`; returns its exit code, stdout+stderr in *output.
int RunCli(const std::string& args, const std::filesystem::path& dir, std::string* output) {
  return testing::RunGroundline("eval " + args, dir, output);
}

class EvalCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::groundline::testing::ScratchDir("eval");
    core::Trajectory reference, offset, rotated;
    for (int i = 0; i < 100; ++i) {
      const double t = 0.1 * i;
      reference.push_back({t, core::SE2(t, 0.0, 0.0), std::nullopt});
      offset.push_back({t, core::SE2(t + 0.1, 0.05, 0.0), std::nullopt});
      rotated.push_back({t, core::SE2(1.0, 2.0, 0.5) * core::SE2(t, 0.0, 0.0), std::nullopt});
    }
    ASSERT_TRUE(core::WriteTumTrajectory(dir_ / "ref.tum", reference).ok());
    ASSERT_TRUE(core::WriteTumTrajectory(dir_ / "offset.tum", offset).ok());
    ASSERT_TRUE(
        core::WriteTrajectory(dir_ / "rotated.csv", rotated, core::TrajectoryFormat::kEuroc).ok());
    std::ofstream(dir_ / "ref.relations") << "0.0 1.0 1.0 0 0 0 0 0\n2.0 3.0 1.0 0 0 0 0 0\n";
  }
  std::string Path(const char* name) const { return "'" + (dir_ / name).string() + "'"; }
  std::filesystem::path dir_;
};

TEST_F(EvalCli, OneEstimateWritesOneObjectWithTheEvalMdKeys) {
  std::string out;
  ASSERT_EQ(RunCli("--est " + Path("offset.tum") + " --ref " + Path("ref.tum") + " --json " +
                       Path("eval.json"),
                   dir_, &out),
            0)
      << out;
  const nlohmann::json j = ReadJson(dir_ / "eval.json");
  ASSERT_TRUE(j.is_object());
  for (const char* key : {"n_matched", "n_unmatched", "ate_rmse_m", "ate_mean_m", "ate_median_m",
                          "ate_max_m", "along_rmse_m", "cross_rmse_m", "heading_rmse_deg"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["n_matched"].get<int>(), 100);
  EXPECT_TRUE(j["n_matched"].is_number_integer());
  EXPECT_NEAR(j["along_rmse_m"].get<double>(), 0.1, 1e-6);
  EXPECT_NEAR(j["cross_rmse_m"].get<double>(), 0.05, 1e-6);
  EXPECT_EQ(j["label"], "offset");
  EXPECT_FALSE(j.contains("nees_in_band"));
  EXPECT_NE(out.find("along-track RMSE [m]"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "eval.json.tmp"));
}

TEST_F(EvalCli, SeveralEstimatesWriteAnArrayInOrder) {
  std::string out;
  ASSERT_EQ(RunCli("--est " + Path("offset.tum") + " --est " + Path("rotated.csv") +
                       " --label a --label b --ref " + Path("ref.tum") + " --relations " +
                       Path("ref.relations") + " --align --json " + Path("eval.json"),
                   dir_, &out),
            0)
      << out;
  const nlohmann::json j = ReadJson(dir_ / "eval.json");
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["label"], "a");
  EXPECT_EQ(j[1]["label"], "b");
  EXPECT_NEAR(j[1]["ate_rmse_m"].get<double>(), 0.0, 1e-6);  // aligned
  EXPECT_NEAR(j[1]["align_yaw_deg"].get<double>(), -0.5 * 180.0 / std::numbers::pi, 1e-5);
  EXPECT_EQ(j[1]["rel_n"].get<int>(), 2);
  EXPECT_NEAR(j[1]["rel_trans_mean_m"].get<double>(), 0.0, 1e-6);
  for (const char* key : {"rel_trans_std_m", "rel_rot_mean_deg", "rel_rot_std_deg"}) {
    EXPECT_TRUE(j[0].contains(key)) << key;
  }
}

TEST_F(EvalCli, ExitCodesSeparateUsageFromDataErrors) {
  std::string out;
  EXPECT_EQ(RunCli("--est " + Path("offset.tum"), dir_, &out), 2) << out;
  EXPECT_EQ(RunCli("--est " + Path("offset.tum") + " --ref " + Path("ref.tum") + " --label x" +
                       " --label y",
                   dir_, &out),
            2)
      << out;
  EXPECT_EQ(RunCli("--est " + Path("missing.tum") + " --ref " + Path("ref.tum"), dir_, &out), 1);
  EXPECT_NE(out.find("missing.tum"), std::string::npos) << out;
  EXPECT_EQ(RunCli("--est " + Path("offset.tum") + " --ref " + Path("ref.tum") +
                       " --max-dt-s 0.01 --rpe-m 100",
                   dir_, &out),
            1);
  EXPECT_NE(out.find("RPE"), std::string::npos) << out;
}

}  // namespace
}  // namespace groundline
