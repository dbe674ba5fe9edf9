// mrcal's LENSMODEL_OPENCV* and OpenCV's own projection are the same
// equations: cv::projectPoints with the same distCoeffs gives the same pixels.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <random>
#include <vector>

#include "groundline/calibration/camera_model.h"
#include "groundline/core/random_draws.h"
#include "test_cameras.h"

namespace groundline::calibration {
namespace {

TEST(OpenCvAgreement, ProjectPointsGivesTheSamePixelsForOpenCv4To12) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int models = 0;
  for (const CameraModel& camera : test_cameras::AllTestCameras()) {
    if (camera.family() != LensFamily::kOpenCv4 && camera.family() != LensFamily::kOpenCv5 &&
        camera.family() != LensFamily::kOpenCv8 && camera.family() != LensFamily::kOpenCv12) {
      continue;
    }
    ++models;
    const std::vector<double>& p = camera.intrinsics();
    const cv::Matx33d K(p[0], 0.0, p[2], 0.0, p[1], p[3], 0.0, 0.0, 1.0);
    const std::vector<double> distortion(p.begin() + 4, p.end());
    std::vector<cv::Point3d> points;
    for (int i = 0; i < 1000; ++i) {
      const Eigen::Vector3d p = core::DrawVector<3>(unit, rng);
      points.emplace_back(0.6 * p(0), 0.45 * p(1), 1.0 + 0.5 * p(2));
    }
    std::vector<cv::Point2d> expected;
    cv::projectPoints(points, cv::Vec3d::zeros(), cv::Vec3d::zeros(), K, distortion, expected);
    double worst_px = 0.0;
    for (size_t i = 0; i < points.size(); ++i) {
      core::Result<Eigen::Vector2d> pixel =
          camera.Project(Eigen::Vector3d(points[i].x, points[i].y, points[i].z));
      ASSERT_TRUE(pixel.ok());
      worst_px =
          std::max(worst_px, std::hypot(pixel->x() - expected[i].x, pixel->y() - expected[i].y));
    }
    EXPECT_LT(worst_px, 1e-6) << camera.lens_model();
  }
  EXPECT_EQ(models, 4);
}

// mrcal_unproject agrees with cv::undistortPoints where OpenCV's iteration converges.
TEST(OpenCvAgreement, UndistortPointsGivesTheSameRaysNearTheCentre) {
  const CameraModel camera =
      test_cameras::MakeCamera("LENSMODEL_OPENCV5", test_cameras::OpenCvLeftIntrinsics());
  const std::vector<double>& p = camera.intrinsics();
  const cv::Matx33d K(p[0], 0.0, p[2], 0.0, p[1], p[3], 0.0, 0.0, 1.0);
  const std::vector<double> distortion(p.begin() + 4, p.end());
  std::vector<cv::Point2d> pixels;
  for (double u = 200.0; u <= 480.0; u += 40.0) {
    for (double v = 120.0; v <= 360.0; v += 40.0) pixels.emplace_back(u, v);
  }
  std::vector<cv::Point2d> normalized;
  cv::undistortPoints(
      pixels, normalized, K, distortion, cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-15));
  for (size_t i = 0; i < pixels.size(); ++i) {
    core::Result<Eigen::Vector3d> ray =
        camera.Unproject({pixels[i].x, pixels[i].y}, RayNormalization::kZEqualsOne);
    ASSERT_TRUE(ray.ok());
    EXPECT_NEAR(ray->x(), normalized[i].x, 1e-8);
    EXPECT_NEAR(ray->y(), normalized[i].y, 1e-8);
  }
}

}  // namespace
}  // namespace groundline::calibration
