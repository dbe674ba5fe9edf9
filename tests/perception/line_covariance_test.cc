// The line covariance model against Monte Carlo, and every analytic Jacobian
// of the covariance chain (back-projection table, pixels -> line,
// intersections) against numeric differentiation.
#include "groundline/perception/line_covariance.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>
#include <string>
#include <vector>

#include "groundline/calibration/camera_model.h"
#include "groundline/core/random_draws.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/junctions.h"
#include "groundline/perception/line_extractor.h"
#include "hesse_line_traits.h"
#include "jacobian_check.h"

namespace groundline::perception {
namespace {

calibration::CameraModel TestCamera() {
  return *calibration::CameraModel::Create(
      "LENSMODEL_OPENCV5", {1132.0, 1131.0, 643.0, 509.0, -0.05, 0.012, 2e-4, -1.5e-4, 0.0}, 1280,
      1024);
}

TEST(LineCovariance, PixelsToLineJacobiansMatchNumeric) {
  const calibration::FloorProjection projection(TestCamera(), calibration::CameraMount{});
  for (const auto& pixels : {std::pair{Eigen::Vector2d(300, 900), Eigen::Vector2d(420, 200)},
                             std::pair{Eigen::Vector2d(100, 600), Eigen::Vector2d(1200, 640)}}) {
    const Eigen::Vector2d& a = pixels.first;  // lambdas capture these
    const Eigen::Vector2d& b = pixels.second;
    Eigen::Matrix2d J1, J2;
    ASSERT_TRUE(LineFromPixels(projection, a, b, &J1, &J2).ok());
    EXPECT_JACOBIAN_NEAR(
        J1, [&](const Eigen::Vector2d& p) { return *LineFromPixels(projection, p, b); }, a, 1e-6);
    EXPECT_JACOBIAN_NEAR(
        J2, [&](const Eigen::Vector2d& p) { return *LineFromPixels(projection, a, p); }, b, 1e-6);
  }
}

TEST(LineCovariance, BackProjectionTableMatchesNumeric) {
  const BevRemap remap(TestCamera(), calibration::CameraMount{}, BevRemap::Options{});
  const calibration::FloorProjection projection(TestCamera(), calibration::CameraMount{});
  const cv::Mat table = FloorFromPixelJacobians(remap.grid(), remap.valid_mask(), projection);
  for (const auto& [col, row] : {std::pair{100, 20}, std::pair{100, 160}, std::pair{60, 90}}) {
    ASSERT_NE(remap.valid_mask().at<std::uint8_t>(row, col), 0);
    const cv::Vec4d j = table.at<cv::Vec4d>(row, col);
    Eigen::Matrix2d J;
    J << j[0], j[1], j[2], j[3];
    const Eigen::Vector2d floor = remap.grid().FloorPointOfCell(Eigen::Vector2d(col, row));
    const Eigen::Vector2d pixel = *projection.PixelOfFloorPoint(floor);
    EXPECT_JACOBIAN_NEAR(
        J, [&](const Eigen::Vector2d& u) { return *projection.FloorPointOfPixel(u); }, pixel, 1e-6);
  }
}

TEST(LineCovariance, IntersectionJacobiansMatchNumeric) {
  const HesseLine a{1.7, 0.05}, b{0.4, 1.6};
  Eigen::Matrix2d Ja, Jb;
  ASSERT_TRUE(IntersectLines(a, b, &Ja, &Jb).ok());
  EXPECT_JACOBIAN_NEAR(
      Ja, [&](const HesseLine& l) { return *IntersectLines(l, b); }, a, 1e-6);
  EXPECT_JACOBIAN_NEAR(
      Jb, [&](const HesseLine& l) { return *IntersectLines(a, l); }, b, 1e-6);
  EXPECT_FALSE(IntersectLines(a, HesseLine{2.0, 0.05}).ok());
}

// Ridge centres along a floor line, seen through the lens with pixel noise:
// the empirical covariance of the fitted (rho, alpha) matches the model.
// The measured-noise model (LineNoiseModel): sigma_px^2 from the scatter with
// N / scatter_correlation_samples degrees of freedom, the covariance counting
// correlation_samples centres per independent one.
TEST(LineCovariance, MeasuredNoiseSeparatesScatterAndMeanCorrelation) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 60; ++i) {
    points.emplace_back(1.0 + 0.01 * i, 0.3 + (i % 2 == 0 ? 0.001 : -0.001));  // +-1 mm
  }
  const std::vector<Eigen::Matrix2d> J(points.size(), 0.002 * Eigen::Matrix2d::Identity());
  LineNoiseModel shared;  // one correlation length for both
  shared.min_sigma_px = 0.01;
  shared.correlation_samples = 4.0;
  LineNoiseModel separate = shared;
  separate.scatter_correlation_samples = 10.0;
  double sigma_shared = 0.0, sigma_separate = 0.0;
  const core::Result<LineFit> a = FitLineWithMeasuredNoise(points, J, shared, &sigma_shared);
  const core::Result<LineFit> b = FitLineWithMeasuredNoise(points, J, separate, &sigma_separate);
  ASSERT_TRUE(a.ok() && b.ok());
  // Residuals of 0.5 px: lambda^2 = 0.25 N_eff / (N_eff - 2), N_eff = 60 / 4
  // or 60 / 10.
  EXPECT_NEAR(sigma_shared * sigma_shared, 0.25 * 15.0 / 13.0, 1e-3);
  EXPECT_NEAR(sigma_separate * sigma_separate, 0.25 * 6.0 / 4.0, 1e-3);
  const core::Result<LineFit> expected = FitLineWithPixelNoise(points, J, sigma_separate, 4.0);
  ASSERT_TRUE(expected.ok());
  EXPECT_TRUE(b->covariance.isApprox(expected->covariance, 1e-6));
  EXPECT_NEAR(b->covariance(1, 1) / a->covariance(1, 1), (6.0 / 4.0) / (15.0 / 13.0), 1e-3);
  LineNoiseModel bad = shared;
  bad.scatter_correlation_samples = 0.5;
  const core::Status status = bad.Validate();
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("scatter_correlation_samples"), std::string::npos);
}

// The floors: an offset of the line and a turn about the centroid of its
// points. Checked against moving the line: a turn by e about the centroid c
// changes (rho, alpha) by (Direction() . c e, e); false: diag(rho^2, alpha^2).
TEST(LineCovariance, FloorsAreAnOffsetAndATurnAboutTheCentroid) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 60; ++i) {
    points.emplace_back(1.2 + 0.01 * i,
                        0.3 + 0.02 * (1.2 + 0.01 * i) + (i % 2 == 0 ? 0.001 : -0.001));
  }
  const std::vector<Eigen::Matrix2d> J(points.size(), 0.002 * Eigen::Matrix2d::Identity());
  LineNoiseModel none;
  none.min_sigma_px = 0.01;
  LineNoiseModel floors = none;
  floors.rho_floor_m = 0.0004;
  floors.alpha_floor_rad = 0.0005;
  LineNoiseModel diagonal = floors;
  diagonal.floor_about_centroid = false;
  const core::Result<LineFit> a = FitLineWithMeasuredNoise(points, J, none);
  const core::Result<LineFit> b = FitLineWithMeasuredNoise(points, J, floors);
  const core::Result<LineFit> c = FitLineWithMeasuredNoise(points, J, diagonal);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) centroid += p / 60.0;
  // The Jacobian of (rho, alpha) to a turn e about the centroid, numerically:
  // the line through the centroid's foot, turned.
  const HesseLine& line = a->line;
  const Eigen::Vector2d foot = centroid - SignedDistance(line, centroid) * line.Normal();
  constexpr double kE = 1e-6;
  const Eigen::Vector2d n_turned(std::cos(line.alpha_rad + kE), std::sin(line.alpha_rad + kE));
  const Eigen::Vector2d d_turn(
      (NormalizeLine(n_turned.dot(foot), line.alpha_rad + kE).rho_m - line.rho_m) / kE, 1.0);
  const Eigen::Matrix2d expected_floor =
      floors.rho_floor_m * floors.rho_floor_m * Eigen::Vector2d(1, 0) * Eigen::RowVector2d(1, 0) +
      floors.alpha_floor_rad * floors.alpha_floor_rad * d_turn * d_turn.transpose();
  EXPECT_TRUE((b->covariance - a->covariance).isApprox(expected_floor, 1e-4))
      << (b->covariance - a->covariance) << "\n"
      << expected_floor;
  const Eigen::Matrix2d diag_floor =
      Eigen::Vector2d(floors.rho_floor_m * floors.rho_floor_m,
                      floors.alpha_floor_rad * floors.alpha_floor_rad)
          .asDiagonal();
  EXPECT_TRUE((c->covariance - a->covariance).isApprox(diag_floor, 1e-9));
  // Sideways play at the centroid: the offset floor alone (the turn pivots there).
  const Eigen::RowVector2d at_centroid(1.0, -line.Direction().dot(centroid));
  const double play_b = at_centroid * (b->covariance - a->covariance) * at_centroid.transpose();
  EXPECT_NEAR(play_b, floors.rho_floor_m * floors.rho_floor_m, 1e-12);
}

TEST(LineCovariance, FitWithPixelNoiseMatchesMonteCarlo) {
  const calibration::FloorProjection projection(TestCamera(), calibration::CameraMount{});
  const HesseLine truth{0.31, 1.52};  // a longitudinal line, 31 cm to the left
  std::vector<Eigen::Vector2d> true_pixels;
  std::vector<Eigen::Matrix2d> jacobians;
  for (double x = 1.0; x <= 2.2; x += 0.02) {
    const Eigen::Vector2d floor =
        truth.rho_m * truth.Normal() +
        (x - truth.rho_m * truth.Normal().x()) / truth.Direction().x() * truth.Direction();
    true_pixels.push_back(*projection.PixelOfFloorPoint(floor));
    Eigen::Matrix2d J;
    ASSERT_TRUE(projection.FloorPointOfPixel(true_pixels.back(), &J).ok());
    jacobians.push_back(J);
  }
  constexpr double kSigmaPx = 0.8;
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, kSigmaPx);
  constexpr int kTrials = 3000;
  std::vector<Eigen::Vector2d> residuals;
  Eigen::Matrix2d model = Eigen::Matrix2d::Zero();
  for (int t = 0; t < kTrials; ++t) {
    std::vector<Eigen::Vector2d> points;
    for (const Eigen::Vector2d& u : true_pixels) {
      points.push_back(*projection.FloorPointOfPixel(u + core::DrawVector<2>(noise, rng)));
    }
    core::Result<LineFit> fit = FitLineWithPixelNoise(points, jacobians, kSigmaPx);
    ASSERT_TRUE(fit.ok()) << fit.message();
    residuals.push_back(LineDifference(fit->line, truth));
    model += fit->covariance / kTrials;
  }
  Eigen::Matrix2d empirical = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& r : residuals) empirical += r * r.transpose() / kTrials;
  EXPECT_NEAR(empirical(0, 0) / model(0, 0), 1.0, 0.15);
  EXPECT_NEAR(empirical(1, 1) / model(1, 1), 1.0, 0.15);
  const double model_corr = model(0, 1) / std::sqrt(model(0, 0) * model(1, 1));
  const double empirical_corr = empirical(0, 1) / std::sqrt(empirical(0, 0) * empirical(1, 1));
  EXPECT_NEAR(empirical_corr, model_corr, 0.1);

  // The two-endpoint form is the same propagation for two points.
  const Eigen::Matrix2d S1 = FloorPointCovariance(jacobians.front(), kSigmaPx);
  const Eigen::Matrix2d S2 = FloorPointCovariance(jacobians.back(), kSigmaPx);
  const std::vector<Eigen::Vector2d> ends = {*projection.FloorPointOfPixel(true_pixels.front()),
                                             *projection.FloorPointOfPixel(true_pixels.back())};
  const std::vector<Eigen::Matrix2d> end_jacobians = {jacobians.front(), jacobians.back()};
  const core::Result<LineEstimate> two = LineFromEndpoints(ends[0], S1, ends[1], S2);
  const core::Result<LineFit> fit_two = FitLineWithPixelNoise(ends, end_jacobians, kSigmaPx);
  ASSERT_TRUE(two.ok() && fit_two.ok());
  EXPECT_LT((two->covariance - fit_two->covariance).norm(), 1e-3 * two->covariance.norm());
}

}  // namespace
}  // namespace groundline::perception
