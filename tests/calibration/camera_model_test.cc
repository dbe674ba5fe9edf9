#include "groundline/calibration/camera_model.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "groundline/core/random_draws.h"
#include "jacobian_check.h"
#include "test_cameras.h"

namespace groundline::calibration {
namespace {

using test_cameras::AllTestCameras;
using test_cameras::MakeCamera;
using test_cameras::RandomPixel;

TEST(CameraModelCreate, RejectsBadModelsWithClearMessages) {
  struct Case {
    std::string model;
    std::vector<double> intrinsics;
    int width, height;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"LENSMODEL_FOO", {1, 1, 1, 1}, 640, 480, "unknown lens model 'LENSMODEL_FOO'"},
      {"LENSMODEL_SPLINED_STEREOGRAPHIC", {1, 1, 1, 1}, 640, 480, "lacks its configuration"},
      {"LENSMODEL_CAHVORE_linearity=0.00", std::vector<double>(12, 1.0), 640, 480,
       "cannot unproject CAHVORE"},
      {"LENSMODEL_OPENCV8",
       {500, 500, 320, 240, 0, 0, 0, 0},
       640,
       480,
       "takes 12 intrinsics, got 8"},
      {"LENSMODEL_PINHOLE", {-500, 500, 320, 240}, 640, 480, "focal lengths must be > 0"},
      {"LENSMODEL_PINHOLE", {500, 500, 320, std::nan("")}, 640, 480, "intrinsics[3] is not finite"},
      {"LENSMODEL_PINHOLE", {500, 500, 320, 240}, 0, 480, "image size must be positive"},
  };
  for (const Case& c : cases) {
    core::Result<CameraModel> camera =
        CameraModel::Create(c.model, c.intrinsics, c.width, c.height);
    ASSERT_FALSE(camera.ok()) << c.model;
    EXPECT_NE(camera.message().find(c.expected), std::string::npos) << camera.message();
  }
}

TEST(CameraModelCreate, KeepsTheConfiguredNameAndFamily) {
  const std::vector<CameraModel> cameras = AllTestCameras();
  EXPECT_EQ(cameras[0].family(), LensFamily::kPinhole);
  EXPECT_EQ(cameras[4].family(), LensFamily::kOpenCv8);
  EXPECT_EQ(cameras[7].family(), LensFamily::kSplinedStereographic);
  EXPECT_EQ(cameras[7].lens_model(),
            "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=11_Ny=8_fov_x_deg=120");
  EXPECT_EQ(cameras[7].intrinsics().size(), 4u + 2u * 11u * 8u);
}

TEST(CameraModelProject, PinholeIsKTimesThePoint) {
  const CameraModel camera = CameraModel::Pinhole(528.0, 531.0, 319.5, 239.5, 640, 480);
  const Eigen::Vector3d p(0.3, -0.2, 2.0);
  core::Result<Eigen::Vector2d> pixel = camera.Project(p);
  ASSERT_TRUE(pixel.ok());
  EXPECT_TRUE(pixel->isApprox((camera.K() * p).hnormalized(), 1e-14));
}

// Unproject then project returns the pixel, everywhere on the imager, for every model.
TEST(CameraModelUnproject, RoundTripsRandomPixelsForEveryModel) {
  std::mt19937 rng(11);
  for (const CameraModel& camera : AllTestCameras()) {
    double worst_px = 0.0;
    for (int i = 0; i < 500; ++i) {
      const Eigen::Vector2d pixel = RandomPixel(camera, rng);
      core::Result<Eigen::Vector3d> ray = camera.Unproject(pixel);
      ASSERT_TRUE(ray.ok()) << camera.lens_model() << ": " << ray.message();
      EXPECT_NEAR(ray->norm(), 1.0, 1e-14);
      core::Result<Eigen::Vector2d> back = camera.Project(*ray);
      ASSERT_TRUE(back.ok()) << camera.lens_model();
      worst_px = std::max(worst_px, (*back - pixel).norm());
      core::Result<Eigen::Vector3d> z1 = camera.Unproject(pixel, RayNormalization::kZEqualsOne);
      ASSERT_TRUE(z1.ok());
      EXPECT_DOUBLE_EQ(z1->z(), 1.0);
      EXPECT_TRUE(z1->normalized().isApprox(*ray, 1e-12));
    }
    EXPECT_LT(worst_px, 1e-10) << camera.lens_model();
  }
}

// Project then unproject gives the direction of the point back.
TEST(CameraModelProject, RoundTripsRandomVisiblePoints) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const CameraModel& camera : AllTestCameras()) {
    int visible = 0;
    for (int i = 0; i < 400; ++i) {
      const Eigen::Vector3d d = core::DrawVector<3>(unit, rng);
      const Eigen::Vector3d p(0.6 * d(0), 0.45 * d(1), 1.0 + 0.5 * d(2));
      if (!camera.IsVisible(p)) continue;
      ++visible;
      core::Result<Eigen::Vector3d> ray = camera.Unproject(*camera.Project(p));
      ASSERT_TRUE(ray.ok()) << camera.lens_model();
      EXPECT_LT((*ray - p.normalized()).norm(), 1e-12) << camera.lens_model();
    }
    EXPECT_GT(visible, 100) << camera.lens_model();
  }
}

TEST(CameraModelProject, JacobianMatchesNumericForEveryModel) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const CameraModel& camera : AllTestCameras()) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d d = core::DrawVector<3>(unit, rng);
      const Eigen::Vector3d p(0.5 * d(0), 0.4 * d(1), 1.2 + 0.5 * d(2));
      Eigen::Matrix<double, 2, 3> J;
      ASSERT_TRUE(camera.Project(p, &J).ok());
      const auto f = [&camera](const Eigen::Vector3d& x) -> Eigen::Vector2d {
        return *camera.Project(x);
      };
      EXPECT_JACOBIAN_NEAR(J, f, p, 1e-6) << camera.lens_model();
    }
  }
}

// The unprojection Jacobian, both normalizations. The input is in units of
// 1/1000 px so that the checker's step (1e-6) is 1e-3 px, well above the
// 1e-11 px unprojection accuracy; the ray is scaled by fx to O(1) entries.
TEST(CameraModelUnproject, JacobianMatchesNumericForEveryModel) {
  std::mt19937 rng(14);
  for (const CameraModel& camera : AllTestCameras()) {
    const double fx = camera.intrinsics()[0];
    for (RayNormalization normalization :
         {RayNormalization::kUnitNorm, RayNormalization::kZEqualsOne}) {
      for (int i = 0; i < 10; ++i) {
        const Eigen::Vector2d pixel = RandomPixel(camera, rng);
        Eigen::Matrix<double, 3, 2> J;
        ASSERT_TRUE(camera.Unproject(pixel, normalization, &J).ok());
        const auto f = [&](const Eigen::Vector2d& kilo_px) -> Eigen::Vector3d {
          return fx * *camera.Unproject(1000.0 * kilo_px, normalization);
        };
        const Eigen::Matrix<double, 3, 2> J_scaled = fx * 1000.0 * J;
        EXPECT_JACOBIAN_NEAR(J_scaled, f, Eigen::Vector2d(pixel / 1000.0), 1e-6)
            << camera.lens_model();
      }
    }
  }
}

TEST(CameraModelBatch, AgreesWithTheSinglePointCalls) {
  std::mt19937 rng(15);
  for (const CameraModel& camera : AllTestCameras()) {
    Eigen::Matrix2Xd pixels(2, 50);
    for (int i = 0; i < pixels.cols(); ++i) pixels.col(i) = RandomPixel(camera, rng);
    pixels.col(7) << std::nan(""), 3.0;  // one bad input
    Eigen::Matrix3Xd rays;
    std::vector<std::uint8_t> valid;
    EXPECT_EQ(camera.UnprojectBatch(pixels, RayNormalization::kZEqualsOne, &rays, &valid), 49);
    EXPECT_EQ(valid[7], 0);
    for (int i = 0; i < pixels.cols(); ++i) {
      if (i == 7) continue;
      ASSERT_EQ(valid[static_cast<size_t>(i)], 1);
      EXPECT_LT(
          (rays.col(i) - *camera.Unproject(pixels.col(i), RayNormalization::kZEqualsOne)).norm(),
          1e-12);
    }

    // Project through a strided view (rows 0-2 of a 4xN block) to exercise the copy.
    Eigen::Matrix4Xd storage = Eigen::Matrix4Xd::Random(4, 50);
    storage.row(2).array() = storage.row(2).array().abs() + 0.5;
    storage(2, 3) = -1.0;  // behind the camera
    Eigen::Matrix2Xd projected;
    Eigen::Matrix<double, 6, Eigen::Dynamic> J;
    const int count = camera.ProjectBatch(storage.topRows<3>(), &projected, &valid, &J);
    const bool behind_ok = camera.family() == LensFamily::kSplinedStereographic ||
                           camera.lens_model() == "LENSMODEL_STEREOGRAPHIC";
    EXPECT_EQ(count, behind_ok ? 50 : 49) << camera.lens_model();
    for (int i = 0; i < 50; ++i) {
      Eigen::Matrix<double, 2, 3> J_single;
      core::Result<Eigen::Vector2d> single = camera.Project(storage.col(i).head<3>(), &J_single);
      ASSERT_EQ(single.ok(), valid[static_cast<size_t>(i)] == 1);
      if (!single.ok()) continue;
      EXPECT_TRUE(projected.col(i).isApprox(*single, 1e-14));
      const Eigen::Map<const Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J_batch(J.col(i).data());
      EXPECT_TRUE(J_batch.isApprox(J_single, 1e-14)) << J_batch << "\n" << J_single;
    }
  }
}

// One model shared by several threads gives the same rays as a serial pass.
TEST(CameraModelThreads, ConcurrentUnprojectionMatchesSerial) {
  const CameraModel camera = AllTestCameras()[7];  // splined: the most state
  std::mt19937 rng(16);
  Eigen::Matrix2Xd pixels(2, 400);
  for (int i = 0; i < pixels.cols(); ++i) pixels.col(i) = RandomPixel(camera, rng);
  Eigen::Matrix3Xd serial;
  std::vector<std::uint8_t> valid;
  ASSERT_EQ(camera.UnprojectBatch(pixels, RayNormalization::kUnitNorm, &serial, &valid), 400);
  std::vector<Eigen::Matrix3Xd> results(4);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < results.size(); ++t) {
    threads.emplace_back([&, t] {
      std::vector<std::uint8_t> ok;
      camera.UnprojectBatch(pixels, RayNormalization::kUnitNorm, &results[t], &ok);
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (const Eigen::Matrix3Xd& rays : results) EXPECT_EQ(rays, serial);
}

TEST(CameraModelValidRegion, PixelsAndPointsInsideTheImageAndInFront) {
  const CameraModel camera = CameraModel::Pinhole(500.0, 500.0, 319.5, 239.5, 640, 480);
  EXPECT_TRUE(camera.InImage({-0.5, -0.5}));
  EXPECT_TRUE(camera.InImage({639.5, 479.5}));
  EXPECT_FALSE(camera.InImage({-0.51, 10.0}));
  EXPECT_FALSE(camera.InImage({10.0, 479.6}));
  EXPECT_TRUE(camera.IsVisible({0.0, 0.0, 1.0}));
  EXPECT_FALSE(camera.IsVisible({0.0, 0.0, -1.0}));  // behind
  EXPECT_FALSE(camera.IsVisible({1.0, 0.0, 1.0}));   // u = 819.5, right of the image
  EXPECT_FALSE(camera.Project({0.0, 0.0, -1.0}).ok());
  EXPECT_FALSE(camera.Project({0.0, 0.0, 0.0}).ok());
  // A stereographic model projects points behind the camera, yet they are not visible.
  const CameraModel wide = MakeCamera("LENSMODEL_STEREOGRAPHIC", {100.0, 100.0, 320.0, 240.0});
  EXPECT_TRUE(wide.Project({1.0, 0.0, -0.1}).ok());
  EXPECT_FALSE(wide.IsVisible({1.0, 0.0, -0.1}));
  // Its sideways pixels have rays with z <= 0: fine as unit rays, not on z = 1.
  const Eigen::Vector2d side = *wide.Project({1.0, 0.0, -0.1});
  EXPECT_TRUE(wide.Unproject(side).ok());
  EXPECT_FALSE(wide.Unproject(side, RayNormalization::kZEqualsOne).ok());
}

}  // namespace
}  // namespace groundline::calibration
