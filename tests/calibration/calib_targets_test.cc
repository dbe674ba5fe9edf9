// The target definitions in calib_targets/targets.yaml describe the real
// boards of ../shared/data: OpenCV finds exactly the declared inner-corner
// grid in their images.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "test_data.h"

namespace groundline {
namespace {

std::map<std::string, YAML::Node> LoadTargets() {
  const YAML::Node root = YAML::LoadFile(GROUNDLINE_CALIB_TARGETS_FILE);
  EXPECT_EQ(root["format"].as<std::string>(), "groundline-calib-targets");
  EXPECT_EQ(root["version"].as<int>(), 1);
  std::map<std::string, YAML::Node> targets;
  for (const YAML::Node& t : root["targets"]) targets[t["name"].as<std::string>()] = t;
  return targets;
}

// Runs the detector with the declared grid; returns the number of corners found.
std::size_t DetectChessboard(const std::filesystem::path& image_path, const YAML::Node& target) {
  const cv::Mat image = cv::imread(image_path.string(), cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(image.empty()) << image_path;
  const cv::Size grid(target["inner_corners_x"].as<int>(), target["inner_corners_y"].as<int>());
  std::vector<cv::Point2f> corners;
  const bool found = cv::findChessboardCorners(
      image, grid, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
  return found ? corners.size() : 0;
}

TEST(CalibTargets, DefinitionsAreCompleteAndPositive) {
  const std::map<std::string, YAML::Node> targets = LoadTargets();
  ASSERT_EQ(targets.size(), 7u);
  for (const auto& [name, t] : targets) {
    const std::string type = t["type"].as<std::string>();
    if (type == "chessboard") {
      EXPECT_GT(t["square_m"].as<double>(), 0.0) << name;
      EXPECT_GE(t["inner_corners_x"].as<int>(), 2) << name;
    } else {
      ASSERT_TRUE(type == "aprilgrid" || type == "floor_tag_sheet") << name;
      EXPECT_EQ(t["family"].as<std::string>(), "tag36h11");
      EXPECT_GT(t["tag_size_m"].as<double>(), 0.0);
    }
  }
}

TEST(CalibTargets, OpenCvChessboardMatchesAllThirteenLeftImages) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const YAML::Node target = LoadTargets().at("opencv_chessboard_9x6_25mm");
  int images = 0;
  for (int i = 1; i <= 14; ++i) {
    if (i == 10) continue;  // the set has no left10.jpg
    char name[32];
    std::snprintf(name, sizeof(name), "left%02d.jpg", i);
    EXPECT_EQ(DetectChessboard(::groundline::testing::SharedDataDir() / "calib/opencv_chessboard" / name, target),
              54u)
        << name;
    ++images;
  }
  EXPECT_EQ(images, 13);
}

TEST(CalibTargets, KalibrCheckerboardMatchesItsImage) {
  GROUNDLINE_REQUIRE_DATA("calib/kalibr_test_images/testImageCheckerboard.jpg");
  const YAML::Node target = LoadTargets().at("kalibr_checkerboard_9x8_50mm");
  EXPECT_EQ(
      DetectChessboard(
          ::groundline::testing::SharedDataDir() / "calib/kalibr_test_images/testImageCheckerboard.jpg", target),
      72u);
  // A wrong declaration is not found: the check can fail.
  YAML::Node wrong = YAML::Clone(target);
  wrong["inner_corners_y"] = 7;
  wrong["inner_corners_x"] = 10;
  EXPECT_EQ(
      DetectChessboard(
          ::groundline::testing::SharedDataDir() / "calib/kalibr_test_images/testImageCheckerboard.jpg", wrong),
      0u);
}

}  // namespace
}  // namespace groundline
