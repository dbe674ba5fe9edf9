// End to end: `groundline sim-commissioning` then `groundline calibrate floor`,
// and the command's errors for bad inputs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "cli_runner.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "test_data.h"

namespace groundline::testing {
namespace {

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(CalibrateFloorCli, RecoversTheSimulatedMountAndReportsErrors) {
  const std::filesystem::path dir = ScratchDir("floor");
  const std::filesystem::path scene = dir / "scene";
  std::string out;
  ASSERT_EQ(RunGroundline("sim-commissioning --small --poses 2 --seed 3 --out " + Quoted(scene),
                          dir, &out),
            0)
      << out;
  const std::string calibrate = "calibrate floor --images " + Quoted(scene / "images") +
                                " --layout " + Quoted(scene / "tag_layout.yaml") + " --camera " +
                                Quoted(scene / "camera.cameramodel") + " --out ";
  ASSERT_EQ(RunGroundline(calibrate + Quoted(dir / "cal"), dir, &out), 0) << out;
  EXPECT_NE(out.find("PASS"), std::string::npos) << out;

  const auto truth = calibration::ReadCameraMountYaml(scene / "true_extrinsics.yaml");
  const auto solved = calibration::ReadCameraMountYaml(dir / "cal" / "extrinsics.yaml");
  ASSERT_TRUE(truth.ok() && solved.ok()) << solved.message();
  EXPECT_NEAR(solved->height_m, truth->height_m, 0.5e-3);
  EXPECT_NEAR(solved->pitch_rad, truth->pitch_rad, 0.02 * M_PI / 180);
  EXPECT_NEAR(solved->roll_rad, truth->roll_rad, 0.02 * M_PI / 180);
  EXPECT_NEAR(solved->yaw_rad, truth->yaw_rad, 0.05 * M_PI / 180);
  const nlohmann::json report = nlohmann::json::parse(ReadText(dir / "cal" / "floor_report.json"));
  EXPECT_EQ(report["verdict"], "PASS");
  EXPECT_EQ(report["bev_error"].size(), 3u);
  EXPECT_EQ(report["images"].size(), 2u);
  EXPECT_LT(report["rms_px"].get<double>(), 0.5);
  EXPECT_GT(report["mount"]["height_mm"]["sigma3"].get<double>(), 0.0);
  EXPECT_NE(ReadText(dir / "cal" / "floor_report.html").find("<svg"), std::string::npos);

  // An image without tags is named and skipped.
  const cv::Mat blank(384, 480, CV_8UC1, cv::Scalar(90));
  ASSERT_TRUE(cv::imwrite((scene / "images" / "pose_001.png").string(), blank));
  ASSERT_EQ(RunGroundline(calibrate + Quoted(dir / "cal1"), dir, &out), 0) << out;
  EXPECT_NE(out.find("pose_001.png: no tag of the layout found; image skipped"), std::string::npos)
      << out;

  // pose_001 replaced by pose_000 shows its tags at the wrong vehicle pose: an
  // outlier image that fails the RMS threshold and is named.
  std::filesystem::copy_file(scene / "images" / "pose_000.png", scene / "images" / "pose_001.png",
                             std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(RunGroundline(calibrate + Quoted(dir / "cal2"), dir, &out), 1) << out;
  EXPECT_NE(out.find("pose_001.png: corner RMS"), std::string::npos) << out;

  // A malformed layout names the file, line and field.
  std::ofstream(dir / "bad.yaml")
      << "format: groundline-tag-layout\nversion: \"1.0\"\n"
         "family: tag36h11\nframe: floor\ntags:\n"
         "  - {id: 1, size_m: zero, pose: {x_m: 0, y_m: 0, yaw_rad: 0}}\n";
  const std::string bad = "calibrate floor --images " + Quoted(scene / "images") + " --layout " +
                          Quoted(dir / "bad.yaml") + " --camera " +
                          Quoted(scene / "camera.cameramodel") + " --out " + Quoted(dir / "cal3");
  EXPECT_EQ(RunGroundline(bad, dir, &out), 1);
  EXPECT_NE(out.find("bad.yaml:6: field 'tags[0].size_m'"), std::string::npos) << out;

  // A base_link layout over a directory of tagless images: nothing to solve.
  std::filesystem::create_directories(dir / "blank");
  std::ofstream(dir / "base.yaml")
      << "format: groundline-tag-layout\nversion: \"1.0\"\n"
         "family: tag36h11\nframe: base_link\ntags:\n"
         "  - {id: 1, size_m: 0.2, pose: {x_m: 1, y_m: 0, yaw_rad: 0}}\n";
  EXPECT_EQ(RunGroundline("calibrate floor --images " + Quoted(dir / "blank") + " --layout " +
                              Quoted(dir / "base.yaml") + " --camera " +
                              Quoted(scene / "camera.cameramodel") + " --out " + Quoted(dir / "c4"),
                          dir, &out),
            1);
  EXPECT_NE(out.find("no image files"), std::string::npos) << out;
}

}  // namespace
}  // namespace groundline::testing
