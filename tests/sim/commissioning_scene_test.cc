// The commissioning scene renders tags that libapriltag finds where the truth
// says they are.
#include "groundline/sim/commissioning_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/floor_extrinsics.h"
#include "groundline/calibration/tag_detection.h"
#include "test_data.h"

namespace groundline::sim {
namespace {

using calibration::TagDetection;

struct CornerStats {
  int tags_expected = 0;
  int tags_found = 0;
  double rms_px = 0.0;
  double max_px = 0.0;
  double mean_x_px = 0.0;
  double mean_y_px = 0.0;
};

// Compares the detections of every image with the projection of the true
// corners; a tag is expected when its corners lie >= margin px inside the image.
CornerStats CompareWithTruth(const CommissioningScene& scene, const std::vector<GreyImage>& images,
                             double margin_px) {
  CornerStats st;
  double sum_sq = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < images.size(); ++k) {
    const GreyImage& im = images[k];
    const std::vector<TagDetection> found =
        calibration::DetectTags(im.pixels.data(), im.width_px, im.height_px, im.width_px);
    const core::SE2& T_floor_base = scene.layout.vehicle_poses[k].T_floor_base;
    for (const calibration::SurveyedTag& tag : scene.layout.tags) {
      bool inside = true;
      std::array<Eigen::Vector2d, 4> truth;
      const auto corners = tag.CornersInFrame();
      for (int c = 0; c < 4; ++c) {
        core::Result<Eigen::Vector2d> px = calibration::PredictFloorPixel(
            scene.camera, scene.true_mount, T_floor_base, corners[c]);
        inside = inside && px.ok() && px->x() > margin_px && px->y() > margin_px &&
                 px->x() < im.width_px - 1 - margin_px && px->y() < im.height_px - 1 - margin_px;
        if (px.ok()) truth[c] = *px;
      }
      const TagDetection* det = nullptr;
      for (const TagDetection& d : found) {
        if (d.id == tag.id) det = &d;
      }
      if (!inside) continue;
      ++st.tags_expected;
      if (det == nullptr) continue;
      ++st.tags_found;
      for (int c = 0; c < 4; ++c) {
        const Eigen::Vector2d e = det->corners_px[c] - truth[c];
        sum_sq += e.squaredNorm();
        st.mean_x_px += e.x();
        st.mean_y_px += e.y();
        st.max_px = std::max(st.max_px, e.norm());
        ++n;
      }
    }
  }
  if (n > 0) {
    st.rms_px = std::sqrt(sum_sq / n);
    st.mean_x_px /= n;
    st.mean_y_px /= n;
  }
  return st;
}

TEST(CommissioningScene, AprilTagFindsEveryTagAtItsTrueCorners) {
  CommissioningOptions options = CommissioningOptions::Small();
  options.poses = 2;  // CI time; the detector's border margin is 4 px, the check's 5
  core::Result<CommissioningScene> scene = MakeCommissioningScene(options);
  ASSERT_TRUE(scene.ok()) << scene.message();
  core::Result<std::vector<GreyImage>> images = RenderCommissioningImages(*scene, options);
  ASSERT_TRUE(images.ok()) << images.message();
  const CornerStats st = CompareWithTruth(*scene, *images, 5.0);
  std::printf("tags expected %d found %d, corner error rms %.3f px max %.3f px mean (%.3f, %.3f)\n",
              st.tags_expected, st.tags_found, st.rms_px, st.max_px, st.mean_x_px, st.mean_y_px);
  EXPECT_GE(st.tags_expected, 8);
  EXPECT_EQ(st.tags_found, st.tags_expected);
  EXPECT_LT(st.rms_px, 0.3);
  EXPECT_LT(std::abs(st.mean_x_px), 0.1);
  EXPECT_LT(std::abs(st.mean_y_px), 0.1);
}

}  // namespace
}  // namespace groundline::sim
