// Lens models with realistic parameters for the calibration tests: one per
// mrcal family groundline supports, all on a 640 x 480 imager.
#ifndef GROUNDLINE_TESTS_CALIBRATION_TEST_CAMERAS_H_
#define GROUNDLINE_TESTS_CALIBRATION_TEST_CAMERAS_H_

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

#include "groundline/calibration/camera_model.h"

namespace groundline::calibration::test_cameras {

inline CameraModel MakeCamera(const std::string& lens_model, const std::vector<double>& intrinsics,
                              int width_px = 640, int height_px = 480) {
  core::Result<CameraModel> camera =
      CameraModel::Create(lens_model, intrinsics, width_px, height_px);
  EXPECT_TRUE(camera.ok()) << camera.message();
  return std::move(camera).value();
}

// OpenCV's published left camera of its chessboard sample (OPENCV5), and
// variations of it for the other OPENCV models.
inline std::vector<double> OpenCvLeftIntrinsics() {
  return {535.9157,  535.9157,  342.2832,    235.5708, -0.26637,
          -0.038589, 0.0017832, -0.00028122, 0.23839};
}

inline std::vector<CameraModel> AllTestCameras() {
  // OpenCV's own left camera without k3 folds back before the image corners;
  // this one is monotonic over the whole image.
  const std::vector<double> opencv4 = {536.1, 535.7, 318.4, 243.2, -0.25, 0.06, 0.0009, -0.0004};
  std::vector<double> opencv8 = {530.2,  531.7,   322.4, 241.9, -0.31, 0.12,
                                 0.0012, -0.0007, 0.02,  0.05,  0.011, 0.002};
  std::vector<double> opencv12 = opencv8;
  opencv12.insert(opencv12.end(), {0.0011, -0.0004, 0.0008, 0.0002});
  std::vector<double> splined = {300.0, 301.5, 322.0, 238.0};
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> knot(-0.02, 0.02);
  for (int i = 0; i < 2 * 11 * 8; ++i) splined.push_back(knot(rng));
  return {
      MakeCamera("LENSMODEL_PINHOLE", {528.0, 531.0, 319.5, 239.5}),
      MakeCamera("LENSMODEL_STEREOGRAPHIC", {300.0, 300.0, 320.0, 240.0}),
      MakeCamera("LENSMODEL_OPENCV4", opencv4),
      MakeCamera("LENSMODEL_OPENCV5", OpenCvLeftIntrinsics()),
      MakeCamera("LENSMODEL_OPENCV8", opencv8),
      MakeCamera("LENSMODEL_OPENCV12", opencv12),
      MakeCamera("LENSMODEL_CAHVOR", {529.0, 530.0, 321.0, 241.0, 0.01, -0.02, 0.001, 0.02, -0.01}),
      MakeCamera("LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=11_Ny=8_fov_x_deg=120", splined),
  };
}

// A uniformly random pixel on the imager.
inline Eigen::Vector2d RandomPixel(const CameraModel& camera, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.5, camera.width_px() - 0.5);
  std::uniform_real_distribution<double> v(-0.5, camera.height_px() - 0.5);
  return {u(rng), v(rng)};
}

}  // namespace groundline::calibration::test_cameras

#endif  // GROUNDLINE_TESTS_CALIBRATION_TEST_CAMERAS_H_
