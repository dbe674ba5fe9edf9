// The self-calibration's state across restarts (mount_estimate_file.h,
// MountSelfCalibrator::Restore) and the mount's uncertainty carried to a floor
// point (FloorPointMountJacobian).
#include "groundline/calibration/mount_estimate_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "jacobian_check.h"
#include "synthetic_aisle.h"
#include "groundline/calibration/mount_remap.h"
#include "groundline/core/angles.h"

namespace groundline::calibration {
namespace {

namespace fs = std::filesystem;
using core::kRadToDeg;
using testing_aisle::Aisle;
using testing_aisle::Difference;
using testing_aisle::Drive;
using testing_aisle::MakeFrame;
using testing_aisle::Moved;

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("groundline_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void Drive_(Drive& d, MountSelfCalibrator& cal, double t0, double t1, const CameraMount& truth) {
  for (double t = t0; t < t1; t += 1.0 / d.rate_hz)
    cal.AddFrame(MakeFrame(d, t, truth, cal.commissioned()));
}

// A restart continues where the last run stopped: the estimate read back is
// the one written (to the last bit of the covariance, the mount within the
// decimal round trip of degrees), and driving on under the same mount
// detects no step.
TEST(MountEstimateFile, ARestartContinuesFromTheSavedEstimate) {
  const fs::path dir = TempDir("mount_estimate_restart");
  Drive d;
  d.world = Aisle(200.0);
  const CameraMount commissioned;
  const CameraMount truth = Moved(commissioned, 1.0, 0.0, -5.0, 0.0);
  MountSelfCalibrator first(commissioned, MountSelfCalibrationOptions{});
  Drive_(d, first, 0.0, 30.0, truth);
  ASSERT_GE(first.estimate().windows_used, 5);
  ASSERT_LT(std::abs(Difference(first.estimate().mount, truth)(kMountPitch)) * kRadToDeg, 0.05);
  ASSERT_TRUE(WriteMountEstimate(dir / "mount_estimate.json", {commissioned, first.estimate()}).ok());

  const core::Result<SavedMountEstimate> saved = ReadMountEstimate(dir / "mount_estimate.json");
  ASSERT_TRUE(saved.ok()) << saved.message();
  EXPECT_TRUE(SameMount(saved->commissioned, commissioned));
  EXPECT_TRUE(SameMount(saved->estimate.mount, first.estimate().mount, 1e-12));
  EXPECT_EQ(saved->estimate.covariance, first.estimate().covariance);
  EXPECT_EQ(saved->estimate.windows_used, first.estimate().windows_used);

  MountSelfCalibrator second(commissioned, MountSelfCalibrationOptions{});
  ASSERT_TRUE(second.Restore(saved->commissioned, saved->estimate).ok());
  EXPECT_TRUE(SameMount(second.estimate().mount, first.estimate().mount, 1e-12));
  const int steps = second.estimate().steps;
  const int windows = second.estimate().windows_used;
  Drive_(d, second, 100.0, 120.0, truth);
  EXPECT_EQ(second.estimate().steps, steps);
  EXPECT_GT(second.estimate().windows_used, windows);
  EXPECT_LT(std::abs(Difference(second.estimate().mount, truth)(kMountPitch)) * kRadToDeg, 0.05);
  EXPECT_FALSE(second.estimate().alarm);
}

// A knocked camera stays alarmed over a restart; a recommissioned one (another
// commissioned mount) does not take the old estimate.
TEST(MountEstimateFile, RestoreKeepsTheAlarmAndRefusesAnotherCommissioning) {
  const CameraMount commissioned;
  MountEstimate knocked;
  knocked.mount = Moved(commissioned, 0.3, -0.4, 0.0, 1.2);
  knocked.covariance = MountMatrix::Identity() * 1e-8;
  knocked.alarm = true;
  knocked.alarm_message = "camera mount moved from its commissioning: roll changed by -0.40 deg";
  MountSelfCalibrator cal(commissioned, MountSelfCalibrationOptions{});
  ASSERT_TRUE(cal.Restore(commissioned, knocked).ok());
  EXPECT_TRUE(cal.estimate().alarm);
  EXPECT_NE(cal.estimate().alarm_message.find("roll changed by -0.40"), std::string::npos)
      << cal.estimate().alarm_message;

  MountSelfCalibrator recommissioned(knocked.mount, MountSelfCalibrationOptions{});
  const core::Status refused = recommissioned.Restore(commissioned, knocked);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("recommissioned"), std::string::npos) << refused.message();
  EXPECT_FALSE(recommissioned.estimate().alarm);
  EXPECT_TRUE(SameMount(recommissioned.estimate().mount, knocked.mount));
}

TEST(MountEstimateFile, ErrorsNameTheFileAndTheField) {
  const fs::path dir = TempDir("mount_estimate_errors");
  const CameraMount commissioned;
  MountEstimate e;
  e.mount = commissioned;
  e.covariance = MountMatrix::Identity() * 1e-6;
  const fs::path good = dir / "good.json";
  ASSERT_TRUE(WriteMountEstimate(good, {commissioned, e}).ok());
  std::ifstream in(good);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_TRUE(ReadMountEstimate(good).ok());

  const auto with = [&](const std::string& from, const std::string& to) {
    std::string changed = text;
    const std::size_t at = changed.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    changed.replace(at, from.size(), to);
    const fs::path path = dir / "bad.json";
    std::ofstream(path) << changed;
    const core::Result<SavedMountEstimate> read = ReadMountEstimate(path);
    EXPECT_FALSE(read.ok()) << from << " -> " << to;
    return read.ok() ? std::string() : read.message();
  };
  const std::string bad_json = with("{", "[");
  EXPECT_NE(bad_json.find("bad.json"), std::string::npos) << bad_json;
  const std::string format = with("groundline-mount-estimate", "something-else");
  EXPECT_NE(format.find("'format'"), std::string::npos) << format;
  const std::string missing = with("\"height_m\"", "\"height\"");
  EXPECT_NE(missing.find("commissioned.height_m"), std::string::npos) << missing;
  const std::string not_spd = with("1e-06", "-1e-06");
  EXPECT_NE(not_spd.find("'covariance'"), std::string::npos) << not_spd;
  EXPECT_NE(not_spd.find("positive definite"), std::string::npos) << not_spd;
  const std::string alarm = with("\"alarm\": false", "\"alarm\": 3");
  EXPECT_NE(alarm.find("'alarm'"), std::string::npos) << alarm;
  // Nothing half-written: no temporary file is left beside the state.
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().extension(), ".json") << entry.path();
}

// FloorPointMountJacobian against central differences of the remap, at
// points near and far, left and right, under a pitched, rolled, yawed mount.
TEST(FloorPointMountJacobian, MatchesNumericDifferentiation) {
  const CameraMount mount = Moved(CameraMount{}, 0.7, -0.3, 4.0, 0.5);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.8, 0.1), Eigen::Vector2d(2.1, -0.9),
                                  Eigen::Vector2d(1.5, 0.7)}) {
    Eigen::Matrix<double, 2, 4> J;
    ASSERT_TRUE(FloorPointMountJacobian(p, mount, &J));
    const auto f = [&](const Eigen::Vector4d& v) {
      Eigen::Vector2d out;
      EXPECT_TRUE(RemapFloorPoint(
          p, mount, Moved(mount, v(0) * kRadToDeg, v(1) * kRadToDeg, v(2) * 1e3, v(3) * kRadToDeg),
          &out));
      return out;
    };
    EXPECT_JACOBIAN_NEAR(J, f, Eigen::Vector4d(Eigen::Vector4d::Zero()), 1e-6);
  }
}

}  // namespace
}  // namespace groundline::calibration
