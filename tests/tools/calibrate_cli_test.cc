// `groundline targets` and `groundline calibrate intrinsics` end to end.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_runner.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::Quoted;
using testing::ReadText;
using testing::RunGroundline;

TEST(CalibrateCli, TargetsWritesSvgAndPngOfEverySheet) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("targets");
  std::string output;
  ASSERT_EQ(RunGroundline("targets --target chessboard_9x6_20mm_a4 --target floor_tags_a3_200mm "
                          "--dpi 30 --out " +
                              Quoted(dir / "t"),
                          dir, &output),
            0)
      << output;
  EXPECT_TRUE(std::filesystem::exists(dir / "t/chessboard_9x6_20mm_a4.svg"));
  EXPECT_TRUE(std::filesystem::exists(dir / "t/chessboard_9x6_20mm_a4.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "t/floor_tags_a3_200mm_id123.svg"));
  EXPECT_NE(output.find("24 sheet(s) on A3"), std::string::npos) << output;
  EXPECT_EQ(
      RunGroundline("targets --target no_such_board --out " + Quoted(dir / "t"), dir, &output), 2);
  EXPECT_NE(output.find("no target named 'no_such_board'"), std::string::npos) << output;
}

// OpenCV's 13 views leave the imager's outer ring empty and are fewer than
// the guide's 20: the calibration is good where the boards were (RMS 0.18
// px) and FAILs with what to capture next; the files are written anyway.
TEST(CalibrateCli, IntrinsicsOnOpenCvChessboardViewsFailsForCoverageAndWritesEveryFile) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("intrinsics");
  std::string output;
  const std::string images =
      (::groundline::testing::SharedDataDir() / "calib/opencv_chessboard/left*.jpg").string();
  ASSERT_EQ(RunGroundline("calibrate intrinsics --images '" + images +
                              "' --target opencv_chessboard_9x6_25mm --out " + Quoted(dir / "cal"),
                          dir, &output),
            1)
      << output;
  EXPECT_NE(output.find("FAIL: LENSMODEL_OPENCV8, 13 views"), std::string::npos) << output;
  EXPECT_NE(output.find("failed: 13 views < 20"), std::string::npos) << output;
  EXPECT_NE(output.find("failed: image top-left corner (outer 10%): 0 corners < 5"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("to do: capture views with the board pushed into the image's top-left "
                        "corner"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("projection uncertainty at 2 m: worst "), std::string::npos) << output;
  for (const char* file : {"camera.cameramodel", "camera_opencv.yaml", "camera_info.yaml",
                           "report.html", "report.json", "corners.vnl"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "cal" / file)) << file;
  }
  std::ifstream in(dir / "cal/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["verdict"], "FAIL");
  EXPECT_LT(report["rms_px"].get<double>(), 0.3);
  EXPECT_EQ(report["views"].size(), 13u);
  // The uncertainty: small in the middle where the boards were, pixels in
  // the empty corners (mrcal 2.2 gives 7.77 px at pixel 9,469, 2 m).
  const nlohmann::json& worst = report["projection_uncertainty"]["worst"];
  ASSERT_EQ(worst.size(), 4u);
  EXPECT_EQ(worst[1]["range_m"], 2.0);
  EXPECT_NEAR(worst[1]["worst_px"].get<double>(), 7.75, 0.1);
  EXPECT_GT(worst[1]["worst_mm"].get<double>(), 10.0);
  const std::string model = ReadText(dir / "cal/camera.cameramodel");
  EXPECT_NE(model.find("'optimization_inputs': b'"), std::string::npos);
}

// Two calibrations of OpenCV's left camera from disjoint views (7 and 6)
// compared as mrcal compares them: they agree near the centre, where both
// saw boards, to a fraction of a pixel (measured: 0.17 px median in the focus
// circle; mrcal's projection_diff gives the same figures on these files), and
// drift apart towards the corners no board reached.
TEST(CalibrateCli, DiffOfTwoCalibrationsOfOneCameraShowsWhereTheyAgree) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("diff");
  const std::filesystem::path views =
      ::groundline::testing::SharedDataDir() / "calib/opencv_chessboard";
  std::string output;
  for (const auto& [glob, name] :
       {std::pair{"left0[1-7].jpg", "first"}, std::pair{"left1*.jpg", "last"}}) {
    // Too few views for a PASS (exit 1), but every file is written.
    ASSERT_EQ(RunGroundline("calibrate intrinsics --images '" + (views / glob).string() +
                                "' --target opencv_chessboard_9x6_25mm --model LENSMODEL_OPENCV5 "
                                "--out " +
                                Quoted(dir / name),
                            dir, &output),
              1)
        << output;
  }
  const std::string first = Quoted(dir / "first/camera.cameramodel");
  const std::string last = Quoted(dir / "last/camera.cameramodel");
  ASSERT_EQ(RunGroundline("calibrate diff " + first + " " + last + " --out " + Quoted(dir / "d"),
                          dir, &output),
            0)
      << output;
  EXPECT_NE(output.find("fitted on 166 grid points within 80 px of the centre"), std::string::npos)
      << output;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(dir / "d/diff.json"));
  EXPECT_GT(j["focus_median_px"].get<double>(), 0.01);
  EXPECT_LT(j["focus_median_px"].get<double>(), 0.5);
  EXPECT_GT(j["imager_max_px"].get<double>(), 5.0 * j["focus_max_px"].get<double>());
  EXPECT_GT(j["rotation_deg"].get<double>(), 0.0);
  EXPECT_EQ(j["grid"].size(), 60u * 45u);
  const cv::Mat picture = cv::imread((dir / "d/diff.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(picture.empty());
  EXPECT_EQ(picture.cols, 640);
  EXPECT_GT(picture.rows, 480);  // the imager and the scale bar under it

  // A model against itself: nothing to fit, nothing apart.
  ASSERT_EQ(
      RunGroundline("calibrate diff " + first + " " + first + " --out " + Quoted(dir / "self"), dir,
                    &output),
      0)
      << output;
  const nlohmann::json self = nlohmann::json::parse(std::ifstream(dir / "self/diff.json"));
  EXPECT_LT(self["imager_max_px"].get<double>(), 1e-6);

  // Another camera's imager is refused, naming both files and both sizes.
  std::ofstream(dir / "big.cameramodel")
      << "{ 'lensmodel': 'LENSMODEL_PINHOLE', 'intrinsics': [1000, 1000, 639.5, 479.5],\n"
         "  'extrinsics': [0, 0, 0, 0, 0, 0], 'imagersize': [1280, 960] }\n";
  EXPECT_EQ(RunGroundline("calibrate diff " + first + " " + Quoted(dir / "big.cameramodel"), dir,
                          &output),
            1);
  EXPECT_NE(output.find("640x480 against 1280x960"), std::string::npos) << output;
  EXPECT_NE(output.find("big.cameramodel"), std::string::npos) << output;
  EXPECT_EQ(RunGroundline("calibrate diff " + first, dir, &output), 2) << output;
}

TEST(CalibrateCli, UsageErrorsExitTwoWithTheReason) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("usage");
  std::string output;
  EXPECT_EQ(RunGroundline("calibrate intrinsics --images " + Quoted(dir / "none*.png") +
                              " --target opencv_chessboard_9x6_25mm --out " + Quoted(dir / "o"),
                          dir, &output),
            2);
  EXPECT_NE(output.find("no image file matches"), std::string::npos) << output;
  EXPECT_EQ(RunGroundline("calibrate intrinsics --images " + Quoted(dir) +
                              " --target opencv_chessboard_9x6_25mm --model LENSMODEL_CAHVOR "
                              "--out " +
                              Quoted(dir / "o"),
                          dir, &output),
            2);
  EXPECT_NE(output.find("not supported"), std::string::npos) << output;
  EXPECT_EQ(RunGroundline("calibrate", dir, &output), 2);
}

}  // namespace
}  // namespace groundline
