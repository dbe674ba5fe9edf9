// SteerableRidgeFilter on synthetic BEV images of bars, grooves and blobs
// rendered here by supersampling.
#include "groundline/perception/steerable_ridge.h"
#include "test_units.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

namespace groundline::perception {
namespace {

using ::groundline::testing::kDeg;
constexpr int kSize = 161;
constexpr double kBackground = 50.0;

// A bar of width_cells through centre with normal at image angle t (cells),
// intensity background + amplitude inside (area coverage, 8 x 8 supersamples).
cv::Mat RenderBar(double width_cells, double t_rad, Eigen::Vector2d centre, double amplitude) {
  const Eigen::Vector2d normal(std::cos(t_rad), std::sin(t_rad));
  cv::Mat image(kSize, kSize, CV_32F);
  for (int v = 0; v < kSize; ++v) {
    for (int u = 0; u < kSize; ++u) {
      int inside = 0;
      for (int i = 0; i < 8; ++i) {
        for (int j = 0; j < 8; ++j) {
          const Eigen::Vector2d p(u - 0.5 + (j + 0.5) / 8.0, v - 0.5 + (i + 0.5) / 8.0);
          inside += std::abs((p - centre).dot(normal)) <= 0.5 * width_cells ? 1 : 0;
        }
      }
      image.at<float>(v, u) = static_cast<float>(kBackground + amplitude * inside / 64.0);
    }
  }
  return image;
}

cv::Mat RenderDisc(double radius_cells, double amplitude) {
  cv::Mat image(kSize, kSize, CV_32F);
  const Eigen::Vector2d centre(80.0, 80.0);
  for (int v = 0; v < kSize; ++v) {
    for (int u = 0; u < kSize; ++u) {
      int inside = 0;
      for (int i = 0; i < 8; ++i) {
        for (int j = 0; j < 8; ++j) {
          const Eigen::Vector2d p(u - 0.5 + (j + 0.5) / 8.0, v - 0.5 + (i + 0.5) / 8.0);
          inside += (p - centre).norm() <= radius_cells ? 1 : 0;
        }
      }
      image.at<float>(v, u) = static_cast<float>(kBackground + amplitude * inside / 64.0);
    }
  }
  return image;
}

double AngleDifferenceModPi(double a, double b) {
  return std::abs(std::remainder(a - b, std::numbers::pi));
}

TEST(SteerableRidgeTest, SteeredResponsePeaksAtBarOrientationAndCentre) {
  const double t_true = 27.0 * kDeg;
  const Eigen::Vector2d normal(std::cos(t_true), std::sin(t_true));
  const Eigen::Vector2d centre = Eigen::Vector2d(80.0, 80.0) + 0.3 * normal;
  const cv::Mat image = RenderBar(7.0, t_true, centre, 100.0);
  const SteerableRidgeFilter filter(SteerableRidgeOptions{});
  HessianImages hessian;
  filter.Compute(image, &hessian);
  double best_t = 0.0, best = 0.0;
  cv::Mat steered;
  for (double t = 0.0; t < 180.0 * kDeg; t += 0.05 * kDeg) {
    Steer(hessian, t, &steered);
    const float r = steered.at<float>(80, 80);
    if (r < best) best = r, best_t = t;
  }
  EXPECT_LT(AngleDifferenceModPi(best_t, t_true), 1.0 * kDeg);
  RidgeImages ridges;
  AnalyzeRidges(hessian, &ridges);
  EXPECT_LT(AngleDifferenceModPi(ridges.normal_rad.at<float>(80, 80), t_true), 1.0 * kDeg);
  // Sub-cell centre along row 80: parabola through the maximum of the bright
  // response and its two neighbours; the bar crosses the row at u = 80 + 0.3 / cos t.
  const float* row = ridges.bright.ptr<float>(80);
  int best_u = 70;
  for (int u = 70; u <= 90; ++u) {
    if (row[u] > row[best_u]) best_u = u;
  }
  const double curvature = row[best_u - 1] - 2.0 * row[best_u] + row[best_u + 1];
  ASSERT_LT(curvature, 0.0);
  const double u_peak = best_u - 0.5 * (row[best_u + 1] - row[best_u - 1]) / curvature;
  const double across_error_cells = (u_peak - (80.0 + 0.3 / normal.x())) * normal.x();
  EXPECT_LT(std::abs(across_error_cells), 0.1);
}

TEST(SteerableRidgeTest, SteeringEqualsDirectFilteringWithRotatedKernel) {
  cv::Mat noise(kSize, kSize, CV_32F), smooth;
  cv::RNG rng(11);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 100.0);
  cv::GaussianBlur(noise, smooth, cv::Size(0, 0), 1.5);
  // Zero mean: the truncated analytic kernel below does not sum to exactly 0.
  cv::Mat image = RenderBar(6.0, 63.0 * kDeg, {79.2, 81.7}, 120.0) + smooth;
  image -= cv::mean(image);
  SteerableRidgeOptions options;
  options.sigma_cells = 3.0;
  options.kernel_radius_sigmas = 6.0;  // negligible truncation: the analytic kernel is exact
  const SteerableRidgeFilter filter(options);
  HessianImages hessian;
  filter.Compute(image, &hessian);
  const double sigma = options.sigma_cells;
  const int radius = filter.radius_cells();
  for (const double t_deg : {0.0, 17.0, 45.0, 90.0, 133.0}) {
    const double c = std::cos(t_deg * kDeg), s = std::sin(t_deg * kDeg);
    cv::Mat kernel(2 * radius + 1, 2 * radius + 1, CV_32F);
    for (int i = -radius; i <= radius; ++i) {
      for (int j = -radius; j <= radius; ++j) {
        const double along = j * c + i * s;  // offset (du, dv) = (j, i) along the direction
        const double g = std::exp(-0.5 * (i * i + j * j) / (sigma * sigma)) /
                         (2.0 * std::numbers::pi * sigma * sigma);
        kernel.at<float>(i + radius, j + radius) = static_cast<float>(
            sigma * sigma * (along * along / std::pow(sigma, 4) - 1.0 / (sigma * sigma)) * g);
      }
    }
    cv::Mat direct, steered;
    cv::filter2D(image, direct, CV_32F, kernel, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
    Steer(hessian, t_deg * kDeg, &steered);
    const cv::Rect interior(radius, radius, kSize - 2 * radius, kSize - 2 * radius);
    double max_direct = 0.0, max_diff = 0.0;
    cv::minMaxLoc(cv::abs(direct(interior)), nullptr, &max_direct);
    cv::minMaxLoc(cv::abs(direct(interior) - steered(interior)), nullptr, &max_diff);
    EXPECT_LT(max_diff, 1e-4 * max_direct)
        << "t = " << t_deg << " deg, " << max_diff << " vs " << max_direct;
  }
}

TEST(SteerableRidgeTest, SeparatesBrightTapeFromDarkGroove) {
  const SteerableRidgeFilter filter(SteerableRidgeOptions{});                        // sigma 3.5
  const double expected = 2.0 * std::exp(-0.5) / std::sqrt(2.0 * std::numbers::pi);  // 2 t phi(t)
  for (const double amplitude : {100.0, -40.0}) {
    const cv::Mat image = RenderBar(7.0, 0.0, {80.0, 80.0}, amplitude);
    HessianImages hessian;
    filter.Compute(image, &hessian);
    RidgeImages ridges;
    AnalyzeRidges(hessian, &ridges);
    const float bright = ridges.bright.at<float>(80, 80);
    const float dark = ridges.dark.at<float>(80, 80);
    const float strength = ridges.signed_strength.at<float>(80, 80);
    EXPECT_NEAR(strength, -expected * amplitude, 0.01 * expected * std::abs(amplitude));
    if (amplitude > 0) {
      EXPECT_NEAR(bright, expected * amplitude, 0.01 * expected * amplitude);
      EXPECT_LT(dark, 0.01 * bright);
    } else {
      EXPECT_NEAR(dark, -expected * amplitude, -0.01 * expected * amplitude);
      EXPECT_LT(bright, 0.01 * dark);
    }
    // A vertical bar is a longitudinal line in the BEV: the across-vehicle
    // channel L_uu carries it, the along-vehicle channel L_vv does not.
    EXPECT_GT(std::abs(hessian.uu.at<float>(80, 80)),
              50.0 * std::abs(hessian.vv.at<float>(80, 80)));
    cv::Mat along_x;
    Steer(hessian, ImageAngleOfBaseAngle(0.0), &along_x);
    EXPECT_LT(cv::norm(along_x, hessian.vv, cv::NORM_INF), 1e-3);
  }
}

TEST(SteerableRidgeTest, NormalizedResponsePeaksAtTheMatchedScale) {
  EXPECT_DOUBLE_EQ(MatchedSigmaForBarWidth(7.0), 3.5);
  const cv::Mat image = RenderBar(7.0, 0.0, {80.0, 80.0}, 100.0);
  double best_sigma = 0.0, best = 0.0;
  for (double sigma = 2.0; sigma <= 5.01; sigma += 0.25) {
    SteerableRidgeOptions options;
    options.sigma_cells = sigma;
    HessianImages hessian;
    SteerableRidgeFilter(options).Compute(image, &hessian);
    const double response = -hessian.uu.at<float>(80, 80);
    if (response > best) best = response, best_sigma = sigma;
  }
  EXPECT_NEAR(best_sigma, 3.5, 0.26);
}

TEST(SteerableRidgeTest, IsotropicBlobHasEigenRatioNearOneUnlikeABar) {
  const SteerableRidgeFilter filter(SteerableRidgeOptions{});
  HessianImages hessian;
  RidgeImages ridges;
  filter.Compute(RenderDisc(4.0, 150.0), &hessian);
  AnalyzeRidges(hessian, &ridges);
  EXPECT_GT(ridges.eigen_ratio.at<float>(80, 80), 0.95f);
  EXPECT_GT(ridges.bright.at<float>(80, 80), 10.0f);  // it is a strong response nonetheless
  filter.Compute(RenderBar(7.0, 35.0 * kDeg, {80.0, 80.0}, 100.0), &hessian);
  AnalyzeRidges(hessian, &ridges);
  EXPECT_LT(ridges.eigen_ratio.at<float>(80, 80), 0.05f);
}

TEST(SteerableRidgeTest, EigenAnalysisMatchesEigenSolver) {
  HessianImages hessian;
  cv::RNG rng(5);
  for (cv::Mat* image : {&hessian.uu, &hessian.uv, &hessian.vv}) {
    image->create(40, 50, CV_32F);
    rng.fill(*image, cv::RNG::UNIFORM, -30.0, 30.0);
  }
  RidgeImages ridges;
  AnalyzeRidges(hessian, &ridges);
  double worst_angle = 0.0;
  for (int r = 0; r < 40; ++r) {
    for (int c = 0; c < 50; ++c) {
      Eigen::Matrix2d H;
      H << hessian.uu.at<float>(r, c), hessian.uv.at<float>(r, c), hessian.uv.at<float>(r, c),
          hessian.vv.at<float>(r, c);
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(H);
      const Eigen::Vector2d l = solver.eigenvalues();  // ascending
      const int dominant = std::abs(l(0)) > std::abs(l(1)) ? 0 : 1;
      const double tol = 1e-4 * l.cwiseAbs().maxCoeff();
      EXPECT_NEAR(ridges.bright.at<float>(r, c), std::max(0.0, -l(0)), tol);
      EXPECT_NEAR(ridges.dark.at<float>(r, c), std::max(0.0, l(1)), tol);
      EXPECT_NEAR(ridges.signed_strength.at<float>(r, c), l(dominant), tol);
      EXPECT_NEAR(ridges.eigen_ratio.at<float>(r, c),
                  l.cwiseAbs().minCoeff() / l.cwiseAbs().maxCoeff(), 1e-4);
      const Eigen::Vector2d v = solver.eigenvectors().col(dominant);
      const float t = ridges.normal_rad.at<float>(r, c);
      EXPECT_GT(t, -0.5 * std::numbers::pi);
      EXPECT_LE(t, 0.5 * std::numbers::pi + 1e-6);
      worst_angle = std::max(worst_angle, AngleDifferenceModPi(t, std::atan2(v.y(), v.x())));
    }
  }
  EXPECT_LT(worst_angle, 0.02 * kDeg);
}

TEST(SteerableRidgeTest, ValidateRejectsBadScales) {
  SteerableRidgeOptions options;
  options.sigma_cells = 0.1;
  EXPECT_NE(options.Validate().message().find("sigma_cells"), std::string::npos);
  options = SteerableRidgeOptions{};
  options.kernel_radius_sigmas = 1.0;
  EXPECT_NE(options.Validate().message().find("kernel_radius_sigmas"), std::string::npos);
}

}  // namespace
}  // namespace groundline::perception
