// Intrinsic calibration against ground truth: synthetic AprilGrid views of a
// known OPENCV8 camera (partial views, Gaussian noise, seeded).
#include "groundline/calibration/intrinsic_calibration.h"

#include <gtest/gtest.h>

#include <sstream>

#include "synthetic_views.h"

namespace groundline::calibration {
namespace {

// Largest pixel difference between the projections of two cameras at the
// observed corners (individual OPENCV8 parameters are correlated, and outside
// the observed region the fit is an extrapolation; the projection where the
// data is, is what a calibration determines).
double MaxProjectionDifference(const CameraModel& a, const CameraModel& b,
                               const std::vector<CalibrationView>& views) {
  double worst = 0.0;
  for (const CalibrationView& view : views) {
    for (const Eigen::Vector2d& q : view.observation.corners_px) {
      const Eigen::Vector3d ray = *a.Unproject(q);
      worst = std::max(worst, (*b.Project(ray) - *a.Project(ray)).norm());
    }
  }
  return worst;
}

TEST(IntrinsicCalibration, RecoversAKnownOpencv8CameraExactlyFromNoiseFreeViews) {
  const CameraModel truth = testing::TrueOpencv8Camera();
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  const std::vector<CalibrationView> views =
      testing::SyntheticViews(truth, target, grid, 12, 0.0, 5);
  IntrinsicCalibrationOptions options;
  options.regularization = false;  // mrcal's regularization biases by ~1e-3 px
  // With no noise the residual spread is ~1e-6 px and any corner is "far out".
  options.outlier_rejection = false;
  core::Result<IntrinsicCalibration> cal = CalibrateIntrinsics(views, grid, 640, 480, options);
  ASSERT_TRUE(cal.ok()) << cal.message();
  EXPECT_LT(MaxProjectionDifference(truth, cal->camera, views), 1e-3);
  EXPECT_LT(cal->summary.rms_px, 1e-4);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(cal->camera.intrinsics()[i], truth.intrinsics()[i], 1e-2);
  EXPECT_EQ(cal->summary.outliers, 0);
}

// With noise, the focal length trades against the board distance; over the
// observed corners the projection stays within a few tenths of a pixel.
TEST(IntrinsicCalibration, RecoversAKnownOpencv8CameraFromPartialAprilGridViews) {
  const CameraModel truth = testing::TrueOpencv8Camera();
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  const std::vector<CalibrationView> views =
      testing::SyntheticViews(truth, target, grid, 16, 0.1, 7);
  ASSERT_EQ(views.size(), 16u);
  core::Result<IntrinsicCalibration> cal =
      CalibrateIntrinsics(views, grid, 640, 480, IntrinsicCalibrationOptions{});
  ASSERT_TRUE(cal.ok()) << cal.message();
  EXPECT_EQ(cal->camera.lens_model(), "LENSMODEL_OPENCV8");
  EXPECT_LT(MaxProjectionDifference(truth, cal->camera, views), 0.5);
  const std::vector<double>& q = cal->camera.intrinsics();
  EXPECT_NEAR(q[0], 500.0, 1.0);
  EXPECT_NEAR(q[1], 502.0, 1.0);
  EXPECT_NEAR(q[2], 321.0, 1.0);
  EXPECT_NEAR(q[3], 239.0, 1.0);
  // Noise of 0.1 px per coordinate: per-point RMS ~ 0.1 * sqrt(2) less the
  // fitted degrees of freedom.
  EXPECT_NEAR(cal->summary.rms_px, 0.1 * std::sqrt(2.0), 0.03);
  EXPECT_LT(cal->summary.residual_check_px, 1e-6);
  EXPECT_LE(cal->summary.outliers, 0.01 * cal->summary.points);
  ASSERT_TRUE(cal->summary.board_warp_m.has_value());
  EXPECT_LT(std::abs((*cal->summary.board_warp_m)[0]), 1e-3);
}

TEST(IntrinsicCalibration, MrcalRejectsAGrossOutlierCorner) {
  const CameraModel truth = testing::TrueOpencv8Camera();
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  std::vector<CalibrationView> views = testing::SyntheticViews(truth, target, grid, 12, 0.1, 11);
  ASSERT_EQ(views.size(), 12u);
  views[3].observation.corners_px[5] += Eigen::Vector2d(6.0, -4.0);
  core::Result<IntrinsicCalibration> cal =
      CalibrateIntrinsics(views, grid, 640, 480, IntrinsicCalibrationOptions{});
  ASSERT_TRUE(cal.ok()) << cal.message();
  EXPECT_EQ(cal->views[3].outlier[5], 1);
  EXPECT_GT(cal->views[3].residual_px[5].norm(), 5.0);
  EXPECT_LT(cal->summary.worst_px, 1.0);  // inliers only
  EXPECT_LT(MaxProjectionDifference(truth, cal->camera, views), 0.9);
}

TEST(IntrinsicCalibration, PinholeAndOpencv4ModelsAreSelectable) {
  const CameraModel truth = *CameraModel::Create(
      "LENSMODEL_OPENCV4", {480.0, 480.0, 318.0, 242.0, -0.1, 0.02, 0.0, 0.0}, 640, 480);
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  const std::vector<CalibrationView> views =
      testing::SyntheticViews(truth, target, grid, 10, 0.05, 3);
  IntrinsicCalibrationOptions options;
  options.lens_model = "LENSMODEL_OPENCV4";
  core::Result<IntrinsicCalibration> cal = CalibrateIntrinsics(views, grid, 640, 480, options);
  ASSERT_TRUE(cal.ok()) << cal.message();
  EXPECT_EQ(cal->camera.intrinsics().size(), 8u);
  EXPECT_LT(MaxProjectionDifference(truth, cal->camera, views), 0.4);
  options.lens_model = "LENSMODEL_PINHOLE";
  cal = CalibrateIntrinsics(views, grid, 640, 480, options);
  ASSERT_TRUE(cal.ok()) << cal.message();
  EXPECT_EQ(cal->camera.intrinsics().size(), 4u);
  EXPECT_GT(cal->summary.rms_px, 0.5);  // a pinhole cannot fit the distortion
}

TEST(IntrinsicCalibration, RefusesTooFewViewsAndUnsupportedModels) {
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  const std::vector<CalibrationView> views =
      testing::SyntheticViews(testing::TrueOpencv8Camera(), target, grid, 2, 0.1, 5);
  core::Result<IntrinsicCalibration> cal =
      CalibrateIntrinsics(views, grid, 640, 480, IntrinsicCalibrationOptions{});
  ASSERT_FALSE(cal.ok());
  EXPECT_NE(cal.message().find("at least 3"), std::string::npos) << cal.message();
  IntrinsicCalibrationOptions options;
  options.lens_model = "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=16_Ny=12_fov_x_deg=100";
  EXPECT_NE(options.Validate().message().find("not supported"), std::string::npos);
}

TEST(IntrinsicCalibration, CornersVnlListsEveryGridPointOfEveryView) {
  const CalibTarget target = testing::SyntheticAprilGrid();
  const BoardGrid grid = MakeBoardGrid(target);
  const std::vector<CalibrationView> views =
      testing::SyntheticViews(testing::TrueOpencv8Camera(), target, grid, 3, 0.1, 5);
  const std::string vnl = MrcalCornersVnl(views, grid);
  std::istringstream in(vnl);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "# filename x y level");
  int lines = 0, observed = 0;
  while (std::getline(in, line)) {
    ++lines;
    observed += line.find(" - - -") == std::string::npos ? 1 : 0;
  }
  EXPECT_EQ(lines, 3 * grid.width_n * grid.height_n);
  std::size_t corners = 0;
  for (const CalibrationView& v : views) corners += v.observation.corners_px.size();
  EXPECT_EQ(static_cast<std::size_t>(observed), corners);
}

}  // namespace
}  // namespace groundline::calibration
