#include "groundline/calibration/floor_projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "groundline/calibration/camera_extrinsics.h"
#include "jacobian_check.h"
#include "test_cameras.h"
#include "test_units.h"

namespace groundline::calibration {
namespace {

using ::groundline::testing::kDeg;

CameraMount RandomFloorMount(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  CameraMount mount;
  mount.height_m = 0.58 + 0.2 * unit(rng);
  mount.pitch_rad = (40.0 + 15.0 * unit(rng)) * kDeg;
  mount.roll_rad = 3.0 * kDeg * unit(rng);
  mount.yaw_rad = 5.0 * kDeg * unit(rng);
  mount.forward_m = 0.42 + 0.1 * unit(rng);
  mount.lateral_m = 0.05 * unit(rng);
  return mount;
}

// For LENSMODEL_PINHOLE the real-camera floor mapping is the plane-induced
// homography of camera_extrinsics.h, values and Jacobians.
TEST(FloorProjection, PinholeAgreesWithTheIdealFloorHomography) {
  std::mt19937 rng(41);
  const CameraModel camera = CameraModel::Pinhole(1132.0, 1132.0, 640.0, 512.0, 1280, 1024);
  for (int trial = 0; trial < 20; ++trial) {
    const CameraMount mount = RandomFloorMount(rng);
    const FloorProjection projection(camera, mount);
    const Eigen::Matrix3d H_img_floor = FloorToImageHomography(BaseFromCamera(mount), camera.K());
    const Eigen::Matrix3d H_floor_img = ImageToFloorHomography(H_img_floor);
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector2d pixel = test_cameras::RandomPixel(camera, rng);
      Eigen::Matrix2d J, J_ideal;
      core::Result<Eigen::Vector2d> floor = projection.FloorPointOfPixel(pixel, &J);
      core::Result<Eigen::Vector2d> ideal = BackProjectPixel(H_floor_img, pixel, &J_ideal);
      ASSERT_EQ(floor.ok(), ideal.ok());
      if (!floor.ok()) continue;
      EXPECT_LT((*floor - *ideal).norm(), 1e-9 * (1.0 + ideal->norm()));
      EXPECT_LT((J - J_ideal).norm(), 1e-9 * (1.0 + J_ideal.norm()));
      core::Result<Eigen::Vector2d> back = projection.PixelOfFloorPoint(*floor);
      ASSERT_TRUE(back.ok());
      EXPECT_LT((*back - *ProjectFloorPoint(H_img_floor, *floor)).norm(), 1e-7);
      EXPECT_LT((*back - pixel).norm(), 1e-7);
    }
  }
}

TEST(FloorProjection, RoundTripsAndJacobiansForEveryLensModel) {
  std::mt19937 rng(42);
  for (const CameraModel& camera : test_cameras::AllTestCameras()) {
    const FloorProjection projection(camera, RandomFloorMount(rng));
    int checked = 0;
    for (int i = 0; i < 60 && checked < 15; ++i) {
      const Eigen::Vector2d pixel = test_cameras::RandomPixel(camera, rng);
      Eigen::Matrix2d J_floor_pixel;
      core::Result<Eigen::Vector2d> floor = projection.FloorPointOfPixel(pixel, &J_floor_pixel);
      if (!floor.ok() || floor->norm() > 6.0) continue;  // sky, or nearly at the horizon
      ++checked;
      Eigen::Matrix2d J_pixel_floor;
      core::Result<Eigen::Vector2d> back = projection.PixelOfFloorPoint(*floor, &J_pixel_floor);
      ASSERT_TRUE(back.ok()) << camera.lens_model();
      EXPECT_LT((*back - pixel).norm(), 1e-9) << camera.lens_model();
      EXPECT_TRUE((J_pixel_floor * J_floor_pixel).isApprox(Eigen::Matrix2d::Identity(), 1e-8));

      const auto to_pixel = [&](const Eigen::Vector2d& x) -> Eigen::Vector2d {
        return *projection.PixelOfFloorPoint(x);
      };
      EXPECT_JACOBIAN_NEAR(J_pixel_floor, to_pixel, *floor, 1e-6) << camera.lens_model();
      // Pixels in units of 1/1000 px and the floor in mm keep the numeric
      // step (1e-3 px) far above the unprojection accuracy (1e-11 px).
      const auto to_floor = [&](const Eigen::Vector2d& kilo_px) -> Eigen::Vector2d {
        return 1000.0 * *projection.FloorPointOfPixel(1000.0 * kilo_px);
      };
      const Eigen::Matrix2d J_scaled = 1e6 * J_floor_pixel;
      EXPECT_JACOBIAN_NEAR(J_scaled, to_floor, Eigen::Vector2d(pixel / 1000.0), 1e-6)
          << camera.lens_model();
    }
    EXPECT_GE(checked, 10) << camera.lens_model();
  }
}

TEST(FloorProjection, PixelsAboveTheHorizonAndPointsBehindFail) {
  const CameraModel camera = test_cameras::AllTestCameras()[3];  // OPENCV5
  CameraMount mount;
  mount.pitch_rad = 10.0 * kDeg;  // horizon inside the image, near its top
  const FloorProjection projection(camera, mount);
  core::Result<Eigen::Vector2d> sky = projection.FloorPointOfPixel({320.0, 10.0});
  ASSERT_FALSE(sky.ok());
  EXPECT_NE(sky.message().find("above the horizon"), std::string::npos) << sky.message();
  EXPECT_TRUE(projection.FloorPointOfPixel({320.0, 470.0}).ok());
  core::Result<Eigen::Vector2d> behind = projection.PixelOfFloorPoint({-1.0, 0.0});
  ASSERT_FALSE(behind.ok());
  EXPECT_NE(behind.message().find("not in front of the camera"), std::string::npos);
  // Straight ahead on the floor projects onto the image's vertical centre line
  // (no roll, no yaw, no lateral offset).
  const Eigen::Vector2d ahead = *projection.PixelOfFloorPoint({4.0, 0.0});
  EXPECT_TRUE(camera.InImage(ahead));
}

// A level-ish camera: the floor distance of the image's bottom row follows the
// mount geometry, d = forward + height / tan(pitch + angle below the axis).
TEST(FloorProjection, BottomRowDistanceFollowsTheMountGeometry) {
  const CameraModel camera = CameraModel::Pinhole(500.0, 500.0, 319.5, 239.5, 640, 480);
  CameraMount mount;
  mount.height_m = 0.5;
  mount.pitch_rad = 20.0 * kDeg;
  mount.forward_m = 0.3;
  const FloorProjection projection(camera, mount);
  const double below_axis_rad = std::atan((479.5 - 239.5) / 500.0);
  const double expected_m = 0.3 + 0.5 / std::tan(mount.pitch_rad + below_axis_rad);
  core::Result<Eigen::Vector2d> floor = projection.FloorPointOfPixel({319.5, 479.5});
  ASSERT_TRUE(floor.ok());
  EXPECT_NEAR(floor->x(), expected_m, 1e-12);
  EXPECT_NEAR(floor->y(), 0.0, 1e-12);
}

}  // namespace
}  // namespace groundline::calibration
