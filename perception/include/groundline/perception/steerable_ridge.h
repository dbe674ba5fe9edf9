// Steerable second-derivative-of-Gaussian ridge filter on the BEV image
// (Freeman & Adelson 1991, "The design and use of steerable filters"; seed
// paper eqs. 34-40).
//
// Coordinates. The filter works in image coordinates (u, v) = (column, row) of
// the BEV (bev_remap.h): u right, v down, cell units. Three separable basis
// filters of the Gaussian G at scale sigma (cells) give the Hessian of the
// smoothed image, scale-normalized by sigma^2 so that responses compare across
// scales (Lindeberg 1998, gamma = 1):
//
//   L_uu = sigma^2 d2G/du2 * I,  L_uv = sigma^2 d2G/dudv * I,  L_vv = sigma^2 d2G/dv2 * I,
//
// each one cv::sepFilter2D (row kernel x column kernel of the sampled 1D
// Gaussian g, its derivative g' and second derivative g''; g sums to 1, g''
// is corrected to sum 0).
//
// Steering. The second derivative along the unit direction (cos t, sin t) in
// (u, v) is
//
//   R(t) = cos^2(t) L_uu + 2 cos(t) sin(t) L_uv + sin^2(t) L_vv.
//
// Seed paper eq. (38) writes k2 = -2 cos sin: that is the same filter with the
// angle measured the other way round (t -> -t, e.g. v up instead of down); we
// keep the plus sign, and the tests check R(t) against direct filtering with a
// rotated 2D kernel. A line whose normal points along t responds most to R(t).
//
// Vehicle axes. BEV columns run against base y and rows against base x, so
// the base_link Hessian is d2/dx2 = L_vv, d2/dy2 = L_uu, d2/dxdy = L_uv (two
// sign flips cancel), and a base direction phi (from x toward y) is the image
// angle t = pi/2 - phi (mod pi). The two orthogonal channels of eq. (40):
//   d2/dy2 (across the vehicle) = L_uu, strongest on longitudinal lines;
//   d2/dx2 (along the vehicle)  = L_vv, strongest on transverse lines (stop bars, joints).
//
// Polarity. Bright tape on dark concrete is a ridge: the second derivative
// across it is strongly negative. A dark saw-cut joint on light concrete is a
// valley: strongly positive. With the Hessian eigenvalues l_lo <= l_hi,
//   bright = max(0, -l_lo)   (normal along l_lo's eigenvector),
//   dark   = max(0,  l_hi)   (normal along l_hi's eigenvector),
// and eigen_ratio = |l_small| / |l_large| in [0, 1] (0 on an ideal straight
// line, 1 on an isotropic blob: the anisotropy test that rejects glare).
// The angle comes from OpenCV's vectorized atan (cv::cartToPolar), within
// 0.02 deg of the exact eigenvector.
//
// Scale. For a bar of width w (a box profile) the sigma^2-normalized response
// at its centre is -2 t phi(t), t = w / (2 sigma), phi the standard normal
// density, largest at t = 1: the matched scale is sigma = w / 2 (derived in
// MatchedSigmaForBarWidth). The often quoted w / (2 sqrt 3) = w / sqrt(12) is
// the standard deviation of the bar's own profile (variance matching), which
// under sigma^2 normalization gives only 64 % of the peak response. 5-10 cm tape at
// 1 cm cells: sigma 2.5-5 cells; the default 3.5 cells matches 7 cm tape and
// keeps >= 84 % of the peak response over 5-10 cm.
//
// Thread-safety: the filter is immutable after construction; Compute and the
// free functions are const / pure and may run concurrently.
#ifndef GROUNDLINE_PERCEPTION_STEERABLE_RIDGE_H_
#define GROUNDLINE_PERCEPTION_STEERABLE_RIDGE_H_

#include <opencv2/core.hpp>

#include "groundline/core/status.h"

namespace groundline::perception {

// sigma = w / 2, the scale at which the sigma^2-normalized second-derivative
// response at the centre of a bar of width w is largest (any length unit).
double MatchedSigmaForBarWidth(double bar_width);

struct SteerableRidgeOptions {
  double sigma_cells = 3.5;         // Gaussian scale in BEV cells
  double kernel_radius_sigmas = 4;  // kernel half-width = ceil(this * sigma) cells

  // Ok when sigma_cells is finite and in [0.5, 50] and kernel_radius_sigmas in [2, 8].
  core::Status Validate() const;
};

// The scale-normalized Hessian images, CV_32FC1, the size of the input.
struct HessianImages {
  cv::Mat uu;  // sigma^2 d2/du2 (across the vehicle: base d2/dy2)
  cv::Mat uv;  // sigma^2 d2/dudv (= base d2/dxdy)
  cv::Mat vv;  // sigma^2 d2/dv2 (along the vehicle: base d2/dx2)
};

struct RidgeImages {
  cv::Mat bright;           // max(0, -l_lo), CV_32FC1
  cv::Mat dark;             // max(0, l_hi), CV_32FC1
  cv::Mat signed_strength;  // the eigenvalue of larger magnitude (< 0 bright, > 0 dark)
  cv::Mat normal_rad;       // image angle t in (-pi/2, pi/2] of that eigenvalue's eigenvector
  cv::Mat eigen_ratio;      // |l_small| / |l_large|, 0 where both vanish
};

class SteerableRidgeFilter {
 public:
  // Options must be valid (asserted).
  explicit SteerableRidgeFilter(const SteerableRidgeOptions& options);

  // The Hessian of a single-channel image (CV_8U, CV_16U or CV_32F), borders
  // replicated. Writes CV_32FC1 images the size of image into *out (reusing
  // its buffers when they have that size).
  void Compute(const cv::Mat& image, HessianImages* out) const;

  const SteerableRidgeOptions& options() const { return options_; }
  int radius_cells() const { return radius_; }
  // The 1D correlation kernels (CV_32F, 2 radius + 1 taps, index i = offset
  // i - radius), scale normalization folded in: g, sigma g', sigma^2 g''.
  const cv::Mat& smooth_kernel() const { return g_; }
  const cv::Mat& first_kernel() const { return d1_; }
  const cv::Mat& second_kernel() const { return d2_; }

 private:
  SteerableRidgeOptions options_;
  int radius_ = 0;
  cv::Mat g_, d1_, d2_;
};

// R(t) = cos^2 t L_uu + 2 cos t sin t L_uv + sin^2 t L_vv, t the image angle
// in radians (see the file comment). *out is CV_32FC1.
void Steer(const HessianImages& hessian, double t_rad, cv::Mat* out);

// The image angle t = pi/2 - phi of the base_link direction phi (radians).
double ImageAngleOfBaseAngle(double phi_rad);

// The intermediate images of AnalyzeRidges (CV_32FC1, the input's size). A
// caller that analyses frame after frame keeps one and passes it: the buffers
// are allocated by the first frame and reused (cv::Mat::create), so a
// long-running stage does not allocate and free them for every frame.
struct RidgeScratch {
  cv::Mat mean, half_diff, radius, double_angle;
};

// Eigen-decomposition of the 2x2 Hessian at every pixel. The images of *out
// are reused when they already have the right size and type. scratch: where
// the intermediate images live (null: allocated for this call).
void AnalyzeRidges(const HessianImages& hessian, RidgeImages* out, RidgeScratch* scratch = nullptr);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_STEERABLE_RIDGE_H_
