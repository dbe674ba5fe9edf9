#include "groundline/perception/steerable_ridge.h"

#include <cassert>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace groundline::perception {

double MatchedSigmaForBarWidth(double bar_width) {
  // sigma^2 d2/du2 of (box of half-width a) * G at the centre is
  // -2 (a / sigma) phi(a / sigma); d/dt [t exp(-t^2 / 2)] = 0 at t = 1.
  return 0.5 * bar_width;
}

core::Status SteerableRidgeOptions::Validate() const {
  if (!std::isfinite(sigma_cells) || sigma_cells < 0.5 || sigma_cells > 50.0) {
    return core::Status::Error("SteerableRidgeOptions.sigma_cells must be in [0.5, 50] cells");
  }
  if (!std::isfinite(kernel_radius_sigmas) || kernel_radius_sigmas < 2.0 ||
      kernel_radius_sigmas > 8.0) {
    return core::Status::Error("SteerableRidgeOptions.kernel_radius_sigmas must be in [2, 8]");
  }
  return core::Status::Ok();
}

SteerableRidgeFilter::SteerableRidgeFilter(const SteerableRidgeOptions& options)
    : options_(options) {
  assert(options.Validate().ok());
  const double sigma = options.sigma_cells;
  radius_ = static_cast<int>(std::ceil(options.kernel_radius_sigmas * sigma));
  const int n = 2 * radius_ + 1;
  std::vector<double> g(n), d1(n), d2(n);
  double g_sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double i = k - radius_;
    g[k] = std::exp(-0.5 * i * i / (sigma * sigma));
    g_sum += g[k];
  }
  for (double& value : g) value /= g_sum;
  // Correlation kernels: out(x) = sum_i k[i] f(x + i), so the derivative
  // kernels are g'(-i) = (i / sigma^2) g(i) and g''(-i) = g''(i). g'' is made
  // to sum to 0 (no response to constant brightness). Its moments are left
  // alone: renormalizing sum i^2 / 2 g'' to 1 would compensate the truncated
  // tails and inflate the kernel by about 1 % at a 4 sigma radius.
  double d2_sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double i = k - radius_;
    d1[k] = i / (sigma * sigma) * g[k];
    d2[k] = (i * i / (sigma * sigma) - 1.0) / (sigma * sigma) * g[k];
    d2_sum += d2[k];
  }
  g_.create(n, 1, CV_32F);
  d1_.create(n, 1, CV_32F);
  d2_.create(n, 1, CV_32F);
  for (int k = 0; k < n; ++k) {
    g_.at<float>(k) = static_cast<float>(g[k]);
    d1_.at<float>(k) = static_cast<float>(sigma * d1[k]);
    d2_.at<float>(k) = static_cast<float>(sigma * sigma * (d2[k] - d2_sum * g[k]));
  }
}

void SteerableRidgeFilter::Compute(const cv::Mat& image, HessianImages* out) const {
  assert(out != nullptr);
  assert(image.channels() == 1);
  cv::Mat source;
  if (image.depth() == CV_32F) {
    source = image;
  } else {
    image.convertTo(source, CV_32F);
  }
  const cv::Point anchor(-1, -1);
  cv::sepFilter2D(source, out->uu, CV_32F, d2_, g_, anchor, 0.0, cv::BORDER_REPLICATE);
  cv::sepFilter2D(source, out->uv, CV_32F, d1_, d1_, anchor, 0.0, cv::BORDER_REPLICATE);
  cv::sepFilter2D(source, out->vv, CV_32F, g_, d2_, anchor, 0.0, cv::BORDER_REPLICATE);
}

void Steer(const HessianImages& hessian, double t_rad, cv::Mat* out) {
  assert(out != nullptr);
  const double c = std::cos(t_rad);
  const double s = std::sin(t_rad);
  cv::addWeighted(hessian.uu, c * c, hessian.vv, s * s, 0.0, *out, CV_32F);
  cv::scaleAdd(hessian.uv, 2.0 * c * s, *out, *out);
}

double ImageAngleOfBaseAngle(double phi_rad) { return 0.5 * std::numbers::pi - phi_rad; }

void AnalyzeRidges(const HessianImages& hessian, RidgeImages* out, RidgeScratch* scratch) {
  assert(out != nullptr);
  RidgeScratch local;
  RidgeScratch& s = scratch != nullptr ? *scratch : local;
  const cv::Size size = hessian.uu.size();
  out->bright.create(size, CV_32F);
  out->dark.create(size, CV_32F);
  out->signed_strength.create(size, CV_32F);
  out->eigen_ratio.create(size, CV_32F);
  // Vectorized polar form of ((L_uu - L_vv) / 2, L_uv): the radius is half the
  // eigenvalue gap, the angle twice l_hi's eigenvector angle (cv::cartToPolar;
  // OpenCV's fast atan, checked against an exact eigen-solver to 0.02 deg in the tests).
  cv::addWeighted(hessian.uu, 0.5, hessian.vv, 0.5, 0.0, s.mean);
  cv::addWeighted(hessian.uu, 0.5, hessian.vv, -0.5, 0.0, s.half_diff);
  cv::cartToPolar(s.half_diff, hessian.uv, s.radius, s.double_angle);  // angle in [0, 2 pi)
  out->normal_rad.create(size, CV_32F);
  constexpr float kPi = std::numbers::pi_v<float>;
  for (int r = 0; r < size.height; ++r) {
    const float* m = s.mean.ptr<float>(r);
    const float* rad = s.radius.ptr<float>(r);
    const float* angle = s.double_angle.ptr<float>(r);
    float* bright = out->bright.ptr<float>(r);
    float* dark = out->dark.ptr<float>(r);
    float* strength = out->signed_strength.ptr<float>(r);
    float* normal = out->normal_rad.ptr<float>(r);
    float* ratio = out->eigen_ratio.ptr<float>(r);
    for (int c = 0; c < size.width; ++c) {
      const float l_hi = m[c] + rad[c];
      const float l_lo = m[c] - rad[c];
      const bool lo_dominates = std::abs(l_lo) > std::abs(l_hi);
      bright[c] = std::max(0.0f, -l_lo);
      dark[c] = std::max(0.0f, l_hi);
      strength[c] = lo_dominates ? l_lo : l_hi;
      // l_hi's eigenvector at angle / 2 in [0, pi); l_lo's is perpendicular.
      float t = 0.5f * angle[c] + (lo_dominates ? 0.5f * kPi : 0.0f);
      if (t > 0.5f * kPi) t -= kPi;
      if (t > 0.5f * kPi) t -= kPi;
      normal[c] = t;
      const float large = std::max(std::abs(l_lo), std::abs(l_hi));
      const float small = std::min(std::abs(l_lo), std::abs(l_hi));
      ratio[c] = large > 0.0f ? small / large : 0.0f;
    }
  }
}

}  // namespace groundline::perception
