// Camera mount perturbations: the schedule of true mounts, and frames rendered
// through the mount in force at their stamp.
#include "groundline/sim/mount_perturbation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "groundline/sim/sim_run.h"
#include "test_data.h"
#include "test_units.h"

namespace groundline::sim {
namespace {

using ::groundline::testing::kDeg;

// Straight along x at 1 m/s, 100 Hz, for duration_s.
core::Trajectory Straight(double duration_s) {
  core::Trajectory t;
  for (int k = 0; k <= static_cast<int>(std::lround(duration_s * 100)); ++k) {
    t.push_back({0.01 * k, core::SE2(0.01 * k, 0.0, 0.0), std::nullopt});
  }
  return t;
}

TEST(MountPerturbation, StepsAddFromTheirTimeAndDriftSinksPerKilometre) {
  const calibration::CameraMount nominal;
  MountPerturbationOptions options;
  options.steps.push_back({"payload", 2.0, -0.002, 0.5 * kDeg});
  options.steps.push_back({"knock", 5.5, 0.0, -0.2 * kDeg, 0.3 * kDeg, 1.0 * kDeg});
  options.height_loss_m_per_km = 0.08;  // 0.08 mm per metre: one 0.2 mm step every 2.5 m
  ASSERT_TRUE(options.Validate().ok());

  const calibration::CameraMount before = PerturbedMount(nominal, options, 1.99, 1.0);
  EXPECT_EQ(before.pitch_rad, nominal.pitch_rad);
  EXPECT_EQ(before.height_m, nominal.height_m);  // 0.08 mm lost: below one step
  const calibration::CameraMount after = PerturbedMount(nominal, options, 6.0, 5.1);
  EXPECT_NEAR(after.pitch_rad, nominal.pitch_rad + 0.3 * kDeg, 1e-12);
  EXPECT_NEAR(after.roll_rad, 0.3 * kDeg, 1e-12);
  EXPECT_NEAR(after.yaw_rad, 1.0 * kDeg, 1e-12);
  EXPECT_NEAR(after.height_m, nominal.height_m - 0.002 - 0.0004, 1e-12);

  const auto schedule = MountSchedule(nominal, options, Straight(8.0));
  ASSERT_TRUE(schedule.ok()) << schedule.message();
  // Start, the payload at 2 s, drift steps at 2.5, 5 and 7.5 m (1 m/s), the
  // knock at 5.5 s; each on the 100 Hz clock.
  std::vector<double> stamps;
  for (const core::CameraExtrinsicsRecord& r : *schedule) stamps.push_back(r.stamp_s);
  const std::vector<double> expected = {0.0, 2.0, 2.5, 5.0, 5.5, 7.5};
  ASSERT_EQ(stamps.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(stamps[i], expected[i], 0.011);
  EXPECT_EQ(RecordAt(*schedule, 5.4), 3u);
  EXPECT_EQ(RecordAt(*schedule, 5.52), 4u);
  EXPECT_EQ(RecordAt(*schedule, -1.0), 0u);
  EXPECT_NEAR((*schedule)[4].yaw_rad, 1.0 * kDeg, 1e-12);
  EXPECT_NEAR((*schedule)[5].height_m, nominal.height_m - 0.002 - 0.0006, 1e-12);
}

TEST(MountPerturbation, InvalidOptionsAndMountsNameTheField) {
  MountPerturbationOptions options;
  options.steps.push_back({"knock", 1.0, 0.0, 0.0, 0.0, 2.0});
  const core::Status s = options.Validate();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("steps[0].yaw_rad"), std::string::npos) << s.message();
  options.steps = {{"height", 1.0, -0.49}};
  calibration::CameraMount low;
  low.height_m = 0.3;
  const auto schedule = MountSchedule(low, options, Straight(2.0));
  ASSERT_FALSE(schedule.ok());
  EXPECT_NE(schedule.message().find("t = 1 s"), std::string::npos) << schedule.message();
}

// The intensity centroid of the bright marking near `expected` (a 2 cm square).
Eigen::Vector2d Centroid(const cv::Mat& image, const Eigen::Vector2d& expected) {
  const double background = image.at<std::uint8_t>(5, 5);
  double sw = 0, su = 0, sv = 0;
  const int r = 12;
  for (int v = static_cast<int>(expected.y()) - r; v <= static_cast<int>(expected.y()) + r; ++v) {
    for (int u = static_cast<int>(expected.x()) - r; u <= static_cast<int>(expected.x()) + r; ++u) {
      if (u < 0 || v < 0 || u >= image.cols || v >= image.rows) continue;
      const double w = std::max(0.0, image.at<std::uint8_t>(v, u) - background);
      sw += w;
      su += w * u;
      sv += w * v;
    }
  }
  return sw > 0 ? Eigen::Vector2d(su / sw, sv / sw) : Eigen::Vector2d(-1e9, -1e9);
}

// Two frames of a standing vehicle, before and after a knock at 1 s: each
// shows the floor point where the camera model puts it through the true mount
// of its moment (and the knock moves it by many pixels).
TEST(MountPerturbation, FramesAreRenderedThroughTheMountInForce) {
  SimRun run;
  run.world.name = "flat";
  run.world.floor_min_m = Vector2(-20, -20);
  run.world.floor_max_m = Vector2(20, 20);
  const Vector2 point_m(1.3, 0.1);
  FloorMarking dot;
  dot.kind = MarkingKind::kStopBar;
  dot.colour = MarkingColour::kWhite;
  dot.polyline_m = {point_m - Vector2(0.01, 0), point_m + Vector2(0.01, 0)};
  dot.width_m = 0.02;
  run.world.markings.push_back(dot);
  for (int k = 0; k <= 200; ++k) {
    run.route.T_map_base.push_back({0.01 * k, core::SE2(), std::nullopt});
  }
  FloorCameraOptions camera;  // a quarter-size imager keeps the test fast
  camera.width_px = 320;
  camera.height_px = 256;
  camera.focal_px = 283.0;
  FloorRenderOptions render = FloorRenderOptions::Ideal();
  render.supersampling = 8;
  run.camera = SimCamera{*camera.MakeCameraModel(), camera.mount, render};
  MountPerturbationOptions knock;
  knock.steps.push_back({"knock", 1.0, -0.01, 1.5 * kDeg, 0.8 * kDeg, 2.0 * kDeg});
  run.dataset.ground_truth_extrinsics = *MountSchedule(camera.mount, knock, run.route.T_map_base);
  ASSERT_EQ(run.dataset.ground_truth_extrinsics.size(), 2u);
  run.dataset.manifest.name = "knock";
  run.dataset.manifest.camera = core::CameraSensor{320, 256, 1.0};
  run.dataset.images = {{0.5, "000000.png"}, {1.5, "000001.png"}};
  run.dataset.UseDefaultFileNames();
  const auto dir = ::groundline::testing::ScratchDir("mount_perturbation_frames");
  ASSERT_TRUE(WriteSimulatedImages(dir, run, {}, 2).ok());

  for (int frame = 0; frame < 2; ++frame) {
    const calibration::CameraMount mount = ToMount(run.dataset.ground_truth_extrinsics[frame]);
    const auto predict = [&](const calibration::CameraMount& m) {
      const Eigen::Vector3d p_cam =
          calibration::BaseFromCamera(m).inverse() * Eigen::Vector3d(point_m.x(), point_m.y(), 0.0);
      return *run.camera->model.Project(p_cam);
    };
    const Eigen::Vector2d expected = predict(mount);
    const cv::Mat image = cv::imread((dir / "images" / run.dataset.images[frame].file).string(),
                                     cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty());
    const Eigen::Vector2d centroid = Centroid(image, expected);
    EXPECT_NEAR(centroid.x(), expected.x(), 0.15) << "frame " << frame;
    EXPECT_NEAR(centroid.y(), expected.y(), 0.15) << "frame " << frame;
    if (frame == 1) {
      EXPECT_GT((expected - predict(camera.mount)).norm(), 5.0);
    }
  }
}

}  // namespace
}  // namespace groundline::sim
