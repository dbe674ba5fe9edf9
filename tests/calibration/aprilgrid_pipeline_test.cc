// The whole intrinsics pipeline on images: a rendered AprilGrid sheet is
// imaged through a known camera (every camera pixel's ray meets the board
// plane; the sheet is sampled there), the tags are detected with libapriltag
// and the camera is solved by mrcal. Checks the pixel conventions end to end:
// a half-pixel slip between the renderer, the detector and the camera model
// would move cx, cy by 0.5 px.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "groundline/calibration/board_detection.h"
#include "groundline/calibration/intrinsic_calibration.h"
#include "groundline/calibration/target_render.h"
#include "groundline/core/random_draws.h"

namespace groundline::calibration {
namespace {

TEST(AprilGridPipeline, RenderedViewsOfAKnownCameraCalibrateBackToIt) {
  CalibTarget target;
  target.name = "pipeline_grid";
  target.type = TargetType::kAprilGrid;
  target.tags_x = 4;
  target.tags_y = 3;
  target.tag_size_m = 0.06;
  target.spacing_ratio = 0.25;
  target.count = 12;
  const BoardGrid grid = MakeBoardGrid(target);
  const TargetSheet sheet = LayoutTarget(target)->front();
  constexpr double kDpi = 101.6;  // 4 px per mm
  const double s = kDpi / 25.4;
  cv::Mat sheet_image;
  cv::cvtColor(RasterizeSheet(sheet, kDpi), sheet_image, cv::COLOR_BGR2GRAY);
  // About one camera pixel of blur (a camera pixel is ~5 sheet pixels here).
  cv::GaussianBlur(sheet_image, sheet_image, cv::Size(0, 0), 2.5);

  const CameraModel truth = *CameraModel::Create(
      "LENSMODEL_OPENCV5", {260.0, 261.0, 161.3, 119.6, -0.2, 0.05, 0.001, -0.001, 0.0}, 320, 240);
  // Every pixel's ray on the z = 1 plane. OpenCV's undistortPoints inverts the
  // same OPENCV5 equations (camera_model.h); it is used here because it runs
  // at full speed in the sanitizer build, where the polished mrcal
  // unprojection of 77k pixels takes most of the test's time.
  std::vector<cv::Point2d> pixels, normalized;
  for (int v = 0; v < 240; ++v) {
    for (int u = 0; u < 320; ++u) pixels.emplace_back(u, v);
  }
  const std::vector<double>& q_true = truth.intrinsics();
  const cv::Matx33d K(q_true[0], 0, q_true[2], 0, q_true[1], q_true[3], 0, 0, 1);
  const std::vector<double> distortion(q_true.begin() + 4, q_true.end());
  cv::undistortPoints(
      pixels, normalized, K, distortion, cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-14));
  double worst_ray_px = 0.0;
  for (std::size_t i = 0; i < pixels.size(); i += 997) {
    const Eigen::Vector2d q =
        *truth.Project(Eigen::Vector3d(normalized[i].x, normalized[i].y, 1.0));
    worst_ray_px = std::max(worst_ray_px, (q - Eigen::Vector2d(pixels[i].x, pixels[i].y)).norm());
  }
  ASSERT_LT(worst_ray_px, 1e-6);

  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u01(-1.0, 1.0);
  std::vector<CalibrationView> views;
  for (int i = 0; views.size() < 10 && i < 40; ++i) {
    const Eigen::Vector3d angles =
        Eigen::Vector3d(0.5, 0.5, 0.3).cwiseProduct(core::DrawVector<3>(u01, rng));
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(angles(0), Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(angles(1), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(angles(2), Eigen::Vector3d::UnitZ()))
                                  .toRotationMatrix();
    const Eigen::Vector3d d = core::DrawVector<3>(u01, rng);
    const Eigen::Vector3d centre(0.08 * d(0), 0.06 * d(1), 0.36 + 0.05 * d(2));
    const Eigen::Vector3d t = centre - R * Eigen::Vector3d(0.14, 0.1, 0.0);
    cv::Mat map_x(240, 320, CV_32F), map_y(240, 320, CV_32F);
    const Eigen::Vector3d Rt_t = R.transpose() * t;
    for (int k = 0; k < 320 * 240; ++k) {
      const Eigen::Vector3d r_board =
          R.transpose() * Eigen::Vector3d(normalized[k].x, normalized[k].y, 1.0);
      const double lambda = Rt_t.z() / r_board.z();
      const Eigen::Vector3d p = lambda * r_board - Rt_t;  // on the board, z = 0
      map_x.at<float>(k) = static_cast<float>((sheet.origin_x_mm + 1000.0 * p.x()) * s - 0.5);
      map_y.at<float>(k) = static_cast<float>((sheet.origin_y_mm + 1000.0 * p.y()) * s - 0.5);
    }
    cv::Mat image;
    cv::remap(sheet_image, image, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
              cv::Scalar(128));
    core::Result<BoardObservation> obs = DetectBoard(image, target, grid, BoardDetectionOptions{});
    if (obs.ok()) views.push_back({"view" + std::to_string(i), *obs});
  }
  ASSERT_EQ(views.size(), 10u);
  IntrinsicCalibrationOptions options;
  options.lens_model = "LENSMODEL_OPENCV5";
  core::Result<IntrinsicCalibration> cal = CalibrateIntrinsics(views, grid, 320, 240, options);
  ASSERT_TRUE(cal.ok()) << cal.message();
  const std::vector<double>& q = cal->camera.intrinsics();
  std::printf("pipeline: fx %.3f fy %.3f cx %.3f cy %.3f rms %.4f px worst %.4f, %d corners\n",
              q[0], q[1], q[2], q[3], cal->summary.rms_px, cal->summary.worst_px,
              cal->summary.points);
  EXPECT_NEAR(q[0], 260.0, 1.0);
  EXPECT_NEAR(q[1], 261.0, 1.0);
  EXPECT_NEAR(q[2], 161.3, 0.25);
  EXPECT_NEAR(q[3], 119.6, 0.25);
  EXPECT_LT(cal->summary.rms_px, 0.2);  // measured 0.13: blur, resampling, line fits
}

}  // namespace
}  // namespace groundline::calibration
