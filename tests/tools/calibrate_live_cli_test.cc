// `groundline calibrate intrinsics --live` and `calibrate floor --live` end to
// end, on recorded frames through the folder frame source (CI has no camera;
// the live loop is the same code for a camera).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.h"
#include "groundline/sim/commissioning_scene.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::Quoted;
using testing::ReadText;
using testing::RunGroundline;

TEST(CalibrateLiveCli, IntrinsicsFromRecordedFramesGuidesKeepsAndSolvesLikeTheFolderFlow) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("live_intrinsics");
  const std::string uri =
      "folder:" +
      (::groundline::testing::SharedDataDir() / "calib/opencv_chessboard/left*.jpg").string();
  std::string output;
  ASSERT_EQ(RunGroundline("calibrate intrinsics --live '" + uri +
                              "' --target opencv_chessboard_9x6_25mm --out " + Quoted(dir / "cal") +
                              " --save-frames " + Quoted(dir / "kept"),
                          dir, &output),
            1)
      << output;
  // Guidance after each kept view, in the technician's words.
  EXPECT_NE(output.find("[view 1] left01.png kept"), std::string::npos) << output;
  EXPECT_NE(output.find("1 of 20 views; image regions covered"), std::string::npos) << output;
  EXPECT_NE(output.find("still missing: push the board's corners to within 10% of the image's "
                        "top-left corner"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("still missing: hold the board in the image's top-left"), std::string::npos)
      << output;
  EXPECT_NE(output.find("tilt the board about its vertical axis"), std::string::npos) << output;
  EXPECT_NE(output.find("stopped: end of folder"), std::string::npos) << output;
  // One verdict: the guidance ended incomplete, so the report FAILs and
  // carries each line the guidance still asked for.
  EXPECT_NE(output.find("coverage incomplete"), std::string::npos) << output;
  EXPECT_NE(output.find("FAIL: LENSMODEL_OPENCV8, 13 views"), std::string::npos) << output;
  EXPECT_EQ(output.find("PASS"), std::string::npos) << output;
  EXPECT_TRUE(std::filesystem::exists(dir / "cal/camera.cameramodel"));
  const nlohmann::json report = nlohmann::json::parse(ReadText(dir / "cal/report.json"));
  EXPECT_EQ(report["verdict"], "FAIL");
  EXPECT_LT(report["rms_px"].get<double>(), 0.3);
  ASSERT_FALSE(report["live_missing"].empty());
  bool carried = false;
  for (const auto& f : report["failures"]) {
    carried = carried || f.get<std::string>().rfind("live guidance: coverage incomplete: ", 0) == 0;
  }
  EXPECT_TRUE(carried) << report["failures"];

  // The kept frames reproduce the run from a folder: the same model.
  ASSERT_TRUE(std::filesystem::exists(dir / "kept/left01.png"));
  ASSERT_EQ(RunGroundline("calibrate intrinsics --images " + Quoted(dir / "kept") +
                              " --target opencv_chessboard_9x6_25mm --out " + Quoted(dir / "again"),
                          dir, &output),
            1)
      << output;
  EXPECT_EQ(ReadText(dir / "again/camera.cameramodel"), ReadText(dir / "cal/camera.cameramodel"));
}

TEST(CalibrateLiveCli, IntrinsicsMaxViewsStopsEarlyAndUsageErrorsExitTwo) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("live_limits");
  const std::string uri =
      "folder:" +
      (::groundline::testing::SharedDataDir() / "calib/opencv_chessboard/left*.jpg").string();
  std::string output;
  const int code = RunGroundline("calibrate intrinsics --live '" + uri +
                                     "' --target opencv_chessboard_9x6_25mm --max-views 5 "
                                     "--model LENSMODEL_OPENCV5 --out " +
                                     Quoted(dir / "cal"),
                                 dir, &output);
  EXPECT_TRUE(code == 0 || code == 1) << output;  // 5 views may FAIL the quadrant check
  EXPECT_NE(output.find("stopped: --max-views 5 reached; 5 views kept"), std::string::npos)
      << output;
  EXPECT_NE(output.find("coverage incomplete"), std::string::npos) << output;
  EXPECT_TRUE(std::filesystem::exists(dir / "cal/camera.cameramodel"));

  EXPECT_EQ(RunGroundline("calibrate intrinsics --live 'rtsp://camera' --target "
                          "opencv_chessboard_9x6_25mm --out " +
                              Quoted(dir / "x"),
                          dir, &output),
            2);
  EXPECT_NE(output.find("unknown source scheme 'rtsp:'"), std::string::npos) << output;
  EXPECT_EQ(RunGroundline("calibrate intrinsics --target opencv_chessboard_9x6_25mm --out " +
                              Quoted(dir / "x"),
                          dir, &output),
            2);
  EXPECT_NE(output.find("--images or --live"), std::string::npos) << output;
  EXPECT_EQ(RunGroundline("calibrate intrinsics --images " + Quoted(dir) + " --live '" + uri +
                              "' --target opencv_chessboard_9x6_25mm --out " + Quoted(dir / "x"),
                          dir, &output),
            2);
  EXPECT_NE(output.find("excludes"), std::string::npos) << output;
}

TEST(CalibrateLiveCli, FloorFromASimulatedSessionSaysWhichTagsAreMissingAndSolvesLikeTheFolder) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("live_floor");
  const std::filesystem::path scene = dir / "scene";
  std::string output;
  // The scene of `groundline sim-commissioning --small --poses 2`, rendered
  // without supersampling (the command's 3x3 costs a minute under ASan).
  sim::CommissioningOptions options = sim::CommissioningOptions::Small();
  options.seed = options.render.seed = 3;
  options.poses = 2;
  options.render.supersampling = 1;
  core::Result<sim::CommissioningScene> made = sim::MakeCommissioningScene(options);
  ASSERT_TRUE(made.ok()) << made.message();
  core::Result<std::vector<sim::GreyImage>> images = sim::RenderCommissioningImages(*made, options);
  ASSERT_TRUE(images.ok()) << images.message();
  ASSERT_TRUE(sim::WriteCommissioningScene(*made, *images, scene).ok());
  const std::string common = " --layout " + Quoted(scene / "tag_layout.yaml") + " --camera " +
                             Quoted(scene / "camera.cameramodel");
  ASSERT_EQ(RunGroundline("calibrate floor --live folder:" + Quoted(scene / "images") + common +
                              " --out " + Quoted(dir / "live"),
                          dir, &output),
            0)
      << output;
  EXPECT_NE(output.find("[frame 1] pose_000.png kept: tags"), std::string::npos) << output;
  EXPECT_NE(output.find("still missing: not yet seen: tags"), std::string::npos) << output;
  EXPECT_NE(output.find("2 frames kept in"), std::string::npos) << output;
  EXPECT_TRUE(std::filesystem::exists(dir / "live/frames/pose_001.png"));
  ASSERT_EQ(RunGroundline("calibrate floor --images " + Quoted(scene / "images") + common +
                              " --out " + Quoted(dir / "folder"),
                          dir, &output),
            0)
      << output;
  // Lossless frames, the same layout poses: the same solve, to the digit.
  EXPECT_EQ(ReadText(dir / "live/extrinsics.yaml"), ReadText(dir / "folder/extrinsics.yaml"));

  // A stale frames directory would mix sessions.
  EXPECT_EQ(RunGroundline("calibrate floor --live folder:" + Quoted(scene / "images") + common +
                              " --out " + Quoted(dir / "live"),
                          dir, &output),
            2);
  EXPECT_NE(output.find("is not empty"), std::string::npos) << output;
}

}  // namespace
}  // namespace groundline
