#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/core/dataset.h"
#include "groundline/sim/sim_run.h"
#include "test_data.h"
#include "tools_under_test.h"

namespace groundline::sim {
namespace {

// A short zone C run with the camera at 0.1 Hz (a few full-size frames): images, calibration files
// and the dataset read back; the written intrinsics and mount are the renderer's.
TEST(SimCameraRun, WritesImagesAndCalibrationThatReadBack) {
  if (::groundline::testing::Sanitized()) {
    // CI time: full-size renders (~70 s under ASan); SimRun covers the writer under ASan.
    GTEST_SKIP() << "too slow under AddressSanitizer (Debug); runs in the release build";
  }
  SimRunOptions options;
  options.zone = Zone::kC;
  options.route.length_m = 60.0;
  options.seed = 5;
  options.with_lidar = false;
  options.camera_rate_hz = 0.1;
  const core::Result<SimRun> run = SimulateRun(options);
  ASSERT_TRUE(run.ok()) << run.message();
  ASSERT_TRUE(run->camera.has_value());
  ASSERT_TRUE(run->dataset.manifest.camera.has_value());
  const double duration_s =
      run->dataset.ground_truth.back().stamp_s - run->dataset.ground_truth.front().stamp_s;
  EXPECT_NEAR(static_cast<double>(run->dataset.images.size()), duration_s * 0.1, 1.0);

  const auto dir = ::groundline::testing::ScratchDir("sim_camera_run");
  std::vector<std::string> stages;
  ASSERT_TRUE(WriteSimulatedImages(
                  dir, *run,
                  [&stages](std::string_view stage, double fraction) {
                    if (fraction == 0.0) stages.emplace_back(stage);
                  },
                  2)
                  .ok());
  EXPECT_EQ(stages, std::vector<std::string>{"camera"});
  ASSERT_TRUE(core::WriteDataset(dir, run->dataset).ok());

  const core::Result<core::Dataset> read = core::ReadDataset(dir);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->images.size(), run->dataset.images.size());
  ASSERT_TRUE(read->manifest.camera.has_value());
  EXPECT_EQ(read->manifest.camera->image_width_px, 1280);
  EXPECT_EQ(read->manifest.camera->rate_hz, 0.1);

  const core::Result<calibration::CameraModel> camera =
      calibration::ReadCameraModel(dir / read->manifest.camera->intrinsics_file);
  ASSERT_TRUE(camera.ok()) << camera.message();
  EXPECT_EQ(camera->intrinsics(), run->camera->model.intrinsics());
  const core::Result<calibration::CameraMount> mount =
      calibration::ReadCameraMountYaml(dir / read->manifest.camera->extrinsics_file);
  ASSERT_TRUE(mount.ok()) << mount.message();
  EXPECT_NEAR(mount->pitch_rad, options.camera.mount.pitch_rad, 1e-12);
  // Without perturbations the true mount is the nominal one, all run long.
  ASSERT_EQ(read->ground_truth_extrinsics.size(), 1u);
  EXPECT_NEAR(read->ground_truth_extrinsics[0].pitch_rad, options.camera.mount.pitch_rad, 1e-9);

  // Every image decodes as 8-bit grey 1280x1024 and is not blank; frames differ.
  cv::Mat previous;
  for (const core::ImageRecord& record : read->images) {
    const cv::Mat image = cv::imread((dir / "images" / record.file).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(image.type(), CV_8UC1) << record.file;
    ASSERT_EQ(image.cols, 1280);
    ASSERT_EQ(image.rows, 1024);
    double lo, hi;
    cv::minMaxLoc(image, &lo, &hi);
    EXPECT_GT(hi - lo, 20.0) << record.file;
    if (!previous.empty()) {
      EXPECT_GT(cv::norm(image, previous, cv::NORM_L1), 0.0);
    }
    previous = image;
  }
}

}  // namespace
}  // namespace groundline::sim
