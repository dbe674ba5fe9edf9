// libapriltag through DetectTags on AprilTag's own test photos
// (../shared/data/calib/apriltag_photos: NASA Swarmathon images with the
// detections AprilTag's test suite expects, at quad_decimate 1, quad_sigma 0,
// refine_edges 0).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "groundline/calibration/board_detection.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

// Lines "id, (x y), (x y), (x y), (x y)", in libapriltag's pixel convention
// (pixel centres at +0.5); returned in groundline's (centres at integers).
std::vector<TagDetection> ReadExpected(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<TagDetection> tags;
  std::string line;
  while (std::getline(in, line)) {
    TagDetection t;
    double c[8];
    if (std::sscanf(line.c_str(), "%d, (%lf %lf), (%lf %lf), (%lf %lf), (%lf %lf)", &t.id, &c[0],
                    &c[1], &c[2], &c[3], &c[4], &c[5], &c[6], &c[7]) != 9) {
      continue;
    }
    for (int k = 0; k < 4; ++k) t.corners_px[k] = {c[2 * k] - 0.5, c[2 * k + 1] - 0.5};
    tags.push_back(t);
  }
  return tags;
}

double MaxCornerError(const TagDetection& a, const TagDetection& b) {
  double worst = 0.0;
  for (int k = 0; k < 4; ++k) worst = std::max(worst, (a.corners_px[k] - b.corners_px[k]).norm());
  return worst;
}

class AprilTagPhotos : public ::testing::TestWithParam<const char*> {};

TEST_P(AprilTagPhotos, EveryExpectedTagWithinATenthOfAPixel) {
  GROUNDLINE_REQUIRE_DATA("calib/apriltag_photos");
  const std::filesystem::path dir = groundline::testing::SharedDataDir() / "calib/apriltag_photos";
  const std::vector<TagDetection> expected = ReadExpected(dir / (std::string(GetParam()) + ".txt"));
  ASSERT_FALSE(expected.empty());
  const cv::Mat image =
      cv::imread((dir / (std::string(GetParam()) + ".jpg")).string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  TagDetectorOptions options = BoardTagDetectorOptions();
  options.quad_sigma = 0.0;
  options.refine_edges = false;
  options.max_bits_corrected = 2;  // apriltag_detector_add_family's default, as the reference ran
  const std::vector<TagDetection> found = DetectTags(image, options);
  EXPECT_EQ(found.size(), expected.size());
  double worst = 0.0;
  int within_tenth = 0;
  for (const TagDetection& e : expected) {
    const TagDetection* best = nullptr;
    for (const TagDetection& f : found) {
      if (f.id == e.id && (best == nullptr || MaxCornerError(f, e) < MaxCornerError(*best, e))) {
        best = &f;
      }
    }
    ASSERT_NE(best, nullptr) << "tag " << e.id << " at " << e.corners_px[0].transpose();
    for (int k = 0; k < 4; ++k) {
      const double error = (best->corners_px[k] - e.corners_px[k]).norm();
      EXPECT_LT(error, 0.2) << "tag at " << e.corners_px[0].transpose() << " corner " << k;
      within_tenth += error < 0.1 ? 1 : 0;
      worst = std::max(worst, error);
    }
  }
  const int corners = 4 * static_cast<int>(expected.size());
  EXPECT_GE(within_tenth, corners - 1) << "corners within 0.1 px of the reference";
  std::printf("%s: %zu expected, %zu found, %d of %d corners within 0.1 px, worst %.3f px\n",
              GetParam(), expected.size(), found.size(), within_tenth, corners, worst);
}

INSTANTIATE_TEST_SUITE_P(Photos, AprilTagPhotos,
                         ::testing::Values("33369213973_9d9bb4cc96_c", "34085369442_304b6bafd9_c",
                                           "34139872896_defdb2f8d9_c"));

TEST(TagDetectorOptions, ValidateNamesTheBadField) {
  TagDetectorOptions options = BoardTagDetectorOptions();
  EXPECT_TRUE(options.Validate().ok());
  options.quad_decimate = 0.5;
  EXPECT_NE(options.Validate().message().find("quad_decimate"), std::string::npos);
  options = BoardTagDetectorOptions();
  options.max_bits_corrected = 4;
  EXPECT_NE(options.Validate().message().find("max_bits_corrected"), std::string::npos);
}

}  // namespace
}  // namespace groundline::calibration
