// `groundline targets` and `groundline calibrate intrinsics` end to end.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::Quoted;
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
  const std::string model = [&] {
    std::ifstream m(dir / "cal/camera.cameramodel");
    return std::string(std::istreambuf_iterator<char>(m), {});
  }();
  EXPECT_NE(model.find("'optimization_inputs': b'"), std::string::npos);
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
