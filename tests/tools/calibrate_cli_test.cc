// `groundline targets` and `groundline calibrate intrinsics` end to end.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "test_data.h"

namespace groundline {
namespace {

using testing::Quoted;
using testing::RunGroundline;

TEST(CalibrateCli, TargetsWritesSvgAndPngOfEverySheet) {
  const std::filesystem::path dir = testing::ScratchDir("targets");
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

TEST(CalibrateCli, IntrinsicsOnOpenCvChessboardViewsPassesAndWritesEveryFile) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const std::filesystem::path dir = testing::ScratchDir("intrinsics");
  std::string output;
  const std::string images =
      (testing::SharedDataDir() / "calib/opencv_chessboard/left*.jpg").string();
  ASSERT_EQ(RunGroundline("calibrate intrinsics --images '" + images +
                              "' --target opencv_chessboard_9x6_25mm --out " + Quoted(dir / "cal"),
                          dir, &output),
            0)
      << output;
  EXPECT_NE(output.find("PASS: LENSMODEL_OPENCV8, 13 views"), std::string::npos) << output;
  for (const char* file : {"camera.cameramodel", "camera_opencv.yaml", "camera_info.yaml",
                           "report.html", "report.json", "corners.vnl"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "cal" / file)) << file;
  }
  std::ifstream in(dir / "cal/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["verdict"], "PASS");
  EXPECT_LT(report["rms_px"].get<double>(), 0.3);
  EXPECT_EQ(report["views"].size(), 13u);
}

TEST(CalibrateCli, UsageErrorsExitTwoWithTheReason) {
  const std::filesystem::path dir = testing::ScratchDir("usage");
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
