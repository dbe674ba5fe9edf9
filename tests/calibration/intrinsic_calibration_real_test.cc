// Intrinsic calibration on OpenCV's real chessboard views, against OpenCV's
// published reference (left_intrinsics.reference.yml: 13 views,
// CALIB_FIX_ASPECT_RATIO, 5 distortion terms).
#include <gtest/gtest.h>

#include <cmath>

#include "calibration_test_views.h"

namespace groundline::calibration {
namespace {

// left_intrinsics.reference.yml (OpenCV samples/data).
constexpr double kRefFx = 535.91573396163199, kRefCx = 342.28315473308373,
                 kRefCy = 235.57082909788173;
constexpr double kRefAvgError = 0.39259098975581364;  // avg_reprojection_error

TEST(IntrinsicCalibrationReal, FixedAspectSeedReproducesOpenCvReference) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const BoardGrid grid = MakeBoardGrid(testing::TargetNamed("opencv_chessboard_9x6_25mm"));
  const std::vector<CalibrationView> views =
      testing::OpenCvLeftViews(grid, testing::OpenCvSampleDetection());
  ASSERT_EQ(views.size(), 13u);
  IntrinsicCalibrationOptions options;
  options.lens_model = "LENSMODEL_OPENCV5";
  options.seed_fix_aspect_ratio = true;
  options.optimize_board_warp = false;
  core::Result<IntrinsicCalibration> cal = CalibrateIntrinsics(views, grid, 640, 480, options);
  ASSERT_TRUE(cal.ok()) << cal.message();
  const OpenCvSeedResult& seed = cal->opencv_seed;
  EXPECT_NEAR(seed.intrinsics[0], kRefFx, 0.5);
  EXPECT_NEAR(seed.intrinsics[1], kRefFx, 0.5);
  EXPECT_DOUBLE_EQ(seed.intrinsics[0], seed.intrinsics[1]);
  EXPECT_NEAR(seed.intrinsics[2], kRefCx, 0.5);
  EXPECT_NEAR(seed.intrinsics[3], kRefCy, 0.5);
  EXPECT_NEAR(seed.rms_px, kRefAvgError, 0.02 * kRefAvgError);
  // The reference's avg_reprojection_error is sqrt(mean of squared per-view
  // RMS) = the per-point RMS (equal corner counts), not the mean per-view RMS.
  double sum_sq = 0.0;
  for (double e : seed.per_view_rms_px) sum_sq += e * e;
  EXPECT_NEAR(std::sqrt(sum_sq / 13.0), seed.rms_px, 1e-9);
  EXPECT_LT(seed.mean_per_view_rms_px, seed.rms_px);

  std::printf("opencv fixAR: fx %.4f fy %.4f cx %.4f cy %.4f rms %.5f mean/view %.5f\n",
              seed.intrinsics[0], seed.intrinsics[1], seed.intrinsics[2], seed.intrinsics[3],
              seed.rms_px, seed.mean_per_view_rms_px);
}

// mrcal's OPENCV5 solve on the same corners (fx, fy free: mrcal cannot tie
// them) against OpenCV's free-aspect solve of the same views
// (REFERENCE_recomputed_debian_opencv_4.6.txt, "left free": fx 535.89
// fy 535.85 cx 342.28 cy 235.53, rms 0.3926). No outlier rejection, no board
// flex: the same problem as OpenCV's, plus mrcal's light regularization.
TEST(IntrinsicCalibrationReal, MrcalOpencv5MatchesOpenCvFreeAspectSolve) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const BoardGrid grid = MakeBoardGrid(testing::TargetNamed("opencv_chessboard_9x6_25mm"));
  const std::vector<CalibrationView> views =
      testing::OpenCvLeftViews(grid, testing::OpenCvSampleDetection());
  ASSERT_EQ(views.size(), 13u);
  IntrinsicCalibrationOptions options;
  options.lens_model = "LENSMODEL_OPENCV5";
  options.optimize_board_warp = false;
  options.outlier_rejection = false;
  core::Result<IntrinsicCalibration> cal = CalibrateIntrinsics(views, grid, 640, 480, options);
  ASSERT_TRUE(cal.ok()) << cal.message();
  const std::vector<double>& q = cal->camera.intrinsics();
  std::printf("mrcal OPENCV5: fx %.4f fy %.4f cx %.4f cy %.4f rms %.5f worst %.4f\n", q[0], q[1],
              q[2], q[3], cal->summary.rms_px, cal->summary.worst_px);
  EXPECT_NEAR(q[0], 535.89, 0.5);
  EXPECT_NEAR(q[1], 535.85, 0.5);
  EXPECT_NEAR(q[2], 342.28, 0.5);
  EXPECT_NEAR(q[3], 235.53, 0.5);
  EXPECT_NEAR(cal->summary.rms_px, 0.3926, 0.02 * 0.3926);
  EXPECT_EQ(cal->summary.outliers, 0);
  EXPECT_LT(cal->summary.residual_check_px, 1e-6);
}

TEST(IntrinsicCalibrationReal, Opencv8SolveFitsBelowHalfAPixel) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const BoardGrid grid = MakeBoardGrid(testing::TargetNamed("opencv_chessboard_9x6_25mm"));
  const std::vector<CalibrationView> views = testing::OpenCvLeftViews(grid);
  ASSERT_EQ(views.size(), 13u);
  core::Result<IntrinsicCalibration> cal =
      CalibrateIntrinsics(views, grid, 640, 480, IntrinsicCalibrationOptions{});
  ASSERT_TRUE(cal.ok()) << cal.message();
  const std::vector<double>& q = cal->camera.intrinsics();
  ASSERT_EQ(q.size(), 12u);
  std::printf(
      "mrcal OPENCV8: fx %.4f fy %.4f cx %.4f cy %.4f rms %.5f worst %.4f outliers %d "
      "warp %.6g %.6g\n",
      q[0], q[1], q[2], q[3], cal->summary.rms_px, cal->summary.worst_px, cal->summary.outliers,
      (*cal->summary.board_warp_m)[0], (*cal->summary.board_warp_m)[1]);
  EXPECT_LT(cal->summary.rms_px, 0.5);
  EXPECT_LT(cal->summary.residual_check_px, 1e-6);
  EXPECT_NEAR(q[2], kRefCx, 5.0);
  EXPECT_NEAR(q[3], kRefCy, 5.0);
}

}  // namespace
}  // namespace groundline::calibration
