// `groundline calibrate parallels` through the executable on a real image:
// the Duckietown road of floor/duckietown/extrinsics/scenario0 (frame1), its
// camera's intrinsics from cameras.yaml written as an OpenCV calibration
// file, and the mount that the floor chessboard of frame0 gives (computed in
// tests/perception/duckietown_parallel_test.cc: 0.10233 m high, pitch
// 13.662 deg, roll -0.180 deg) with 3 deg more pitch. The check must bring
// the road's two edges parallel again and the pitch back to the board's.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "cli_runner.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/core/angles.h"
#include "test_data.h"

namespace groundline {
namespace {

namespace fs = std::filesystem;
using testing::Quoted;
using testing::RunGroundline;

TEST(CalibrateParallelsCli, BringsTheRoadEdgesOfARealImageParallelAndThePitchToTheBoards) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown/extrinsics/scenario0");
  const fs::path data =
      ::groundline::testing::SharedDataDir() / "floor/duckietown/extrinsics/scenario0";
  const fs::path dir = ::groundline::testing::ScratchDir("calibrate_parallels");
  fs::create_directories(dir / "images");
  fs::copy_file(data / "frame1_distorted.jpg", dir / "images" / "frame1.jpg");
  const core::Result<calibration::CameraModel> camera = calibration::CameraModel::Create(
      "LENSMODEL_OPENCV5",
      {295.79606866959824, 299.5389048862878, 321.2621599038631, 241.73616515312332,
       -0.23543978771661125, 0.03637781479419574, -0.0033069818601306755, -0.0012140708179525926,
       0.0},
      640, 480);
  ASSERT_TRUE(camera.ok()) << camera.message();
  ASSERT_TRUE(calibration::WriteOpenCvCalibration(dir / "camera.yaml", *camera).ok());
  constexpr double kBoardPitchDeg = 13.662;
  calibration::CameraMount start;
  start.height_m = 0.10233;
  start.pitch_rad = (kBoardPitchDeg + 3.0) * core::kDegToRad;
  start.roll_rad = -0.180 * core::kDegToRad;
  start.forward_m = 0.0;
  ASSERT_TRUE(calibration::WriteCameraMountYaml(start, dir / "mount.yaml").ok());

  std::string out;
  ASSERT_EQ(RunGroundline("calibrate parallels " + Quoted(dir / "images") + " --camera " +
                              Quoted(dir / "camera.yaml") + " --extrinsics " +
                              Quoted(dir / "mount.yaml") +
                              " --grid 0.15,0.75,-0.3,0.3,0.0025 --min-line-length 0.04 --out " +
                              Quoted(dir / "out"),
                          dir, &out),
            0)
      << out;
  EXPECT_NE(out.find("lines off parallel: before max"), std::string::npos) << out;
  std::ifstream in(dir / "out" / "parallels.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_GT(j["before_max_off_deg"].get<double>(), 3.0) << j.dump(1);
  EXPECT_LT(j["after_max_off_deg"].get<double>(), 0.5) << j.dump(1);
  ASSERT_FALSE(j["after"].empty()) << j.dump(1);
  const core::Result<calibration::CameraMount> solved =
      calibration::ReadCameraMountYaml(dir / "out" / "extrinsics.yaml");
  ASSERT_TRUE(solved.ok()) << solved.message();
  EXPECT_NEAR(solved->pitch_rad * core::kRadToDeg, kBoardPitchDeg, 0.5);
  EXPECT_EQ(solved->height_m, start.height_m);
  for (const char* name : {"bev_before_frame1.png", "bev_after_frame1.png"}) {
    const cv::Mat png = cv::imread((dir / "out" / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(png.empty()) << name;
    EXPECT_EQ(png.rows, 240) << name;  // 0.6 m ahead in 2.5 mm cells
    EXPECT_EQ(png.cols, 240) << name;
  }
  // A folder with no image is an error that names it.
  fs::create_directories(dir / "empty");
  EXPECT_EQ(RunGroundline("calibrate parallels " + Quoted(dir / "empty") + " --camera " +
                              Quoted(dir / "camera.yaml") + " --out " + Quoted(dir / "out2"),
                          dir, &out),
            1);
  EXPECT_NE(out.find("no readable image"), std::string::npos) << out;
}

}  // namespace
}  // namespace groundline
