#include "groundline/calibration/projection_diff.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <string>

#include "groundline/core/statistics.h"

namespace groundline::calibration {
namespace {

// mrcal's Huber scale on th2 (~ angle^2): (5 deg)^2.
constexpr double kHuberScaleDeg = 5.0;

// th2 = 2 (1 - cos) between R p0 + t and the unit ray v1, as mrcal's fit.
struct RayAngleCost {
  RayAngleCost(const Eigen::Vector3d& p0, const Eigen::Vector3d& v1) : p0_(p0), v1_(v1) {}
  template <typename T>
  bool operator()(const T* r, const T* t, T* residual) const {
    const T p[3] = {T(p0_.x()), T(p0_.y()), T(p0_.z())};
    T q[3];
    ceres::AngleAxisRotatePoint(r, p, q);
    if (t != nullptr) {
      for (int k = 0; k < 3; ++k) q[k] += t[k];
    }
    const T inner = q[0] * v1_.x() + q[1] * v1_.y() + q[2] * v1_.z();
    const T mag = ceres::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    residual[0] = T(2.0) * (T(1.0) - inner / mag);
    return true;
  }
  template <typename T>
  bool operator()(const T* r, T* residual) const {
    return (*this)(r, static_cast<const T*>(nullptr), residual);
  }
  Eigen::Vector3d p0_, v1_;
};

double Max(const std::vector<double>& v) {
  return v.empty() ? std::numeric_limits<double>::quiet_NaN()
                   : *std::max_element(v.begin(), v.end());
}

}  // namespace

core::Status ProjectionDiffOptions::Validate() const {
  if (grid_width < 2 || grid_width > 1000) {
    return core::Status::Error("projection diff: grid_width must be in [2, 1000], got " +
                               std::to_string(grid_width));
  }
  if (grid_height != 0 && (grid_height < 2 || grid_height > 1000)) {
    return core::Status::Error(
        "projection diff: grid_height must be 0 (automatic) or in "
        "[2, 1000], got " +
        std::to_string(grid_height));
  }
  if (!std::isfinite(distance_m) || distance_m < 0.0) {
    return core::Status::Error(
        "projection diff: distance_m must be 0 (infinity) or a finite "
        "positive range, got " +
        std::to_string(distance_m));
  }
  if (!std::isfinite(focus_radius_px)) {
    return core::Status::Error("projection diff: focus_radius_px must be finite (< 0: automatic)");
  }
  return core::Status::Ok();
}

core::Result<ProjectionDiff> ComputeProjectionDiff(const CameraModel& model0,
                                                   const CameraModel& model1,
                                                   const ProjectionDiffOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  const int W = model0.width_px(), H = model0.height_px();
  if (model1.width_px() != W || model1.height_px() != H) {
    return core::Status::Error("projection diff: the imagers differ (" + std::to_string(W) + "x" +
                               std::to_string(H) + " against " + std::to_string(model1.width_px()) +
                               "x" + std::to_string(model1.height_px()) +
                               "): two calibrations of one camera have the same imager");
  }
  ProjectionDiff out;
  out.grid_width = options.grid_width;
  out.grid_height =
      options.grid_height > 0
          ? options.grid_height
          : std::max(
                2, static_cast<int>(std::lround(static_cast<double>(H) / W * options.grid_width)));
  out.focus_radius_px =
      options.focus_radius_px < 0.0 ? std::min(W, H) / 6.0 : options.focus_radius_px;
  const int n = out.grid_width * out.grid_height;
  Eigen::Matrix2Xd pixels(2, n);
  for (int iy = 0; iy < out.grid_height; ++iy) {
    for (int ix = 0; ix < out.grid_width; ++ix) {
      pixels.col(iy * out.grid_width + ix) = Eigen::Vector2d(
          (W - 1.0) * ix / (out.grid_width - 1), (H - 1.0) * iy / (out.grid_height - 1));
    }
  }
  Eigen::Matrix3Xd v0, v1;
  std::vector<std::uint8_t> ok0, ok1;
  model0.UnprojectBatch(pixels, RayNormalization::kUnitNorm, &v0, &ok0);
  model1.UnprojectBatch(pixels, RayNormalization::kUnitNorm, &v1, &ok1);
  const double range = options.distance_m > 0.0 ? options.distance_m : 1.0;
  const Eigen::Vector2d centre((W - 1.0) / 2.0, (H - 1.0) / 2.0);
  std::vector<bool> in_focus(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    in_focus[static_cast<std::size_t>(i)] = (pixels.col(i) - centre).norm() < out.focus_radius_px;
  }

  double r[3] = {0.0, 0.0, 0.0};
  double t[3] = {0.0, 0.0, 0.0};
  if (!options.intrinsics_only) {
    ceres::Problem problem;
    const double huber = std::pow(kHuberScaleDeg * std::numbers::pi / 180.0, 2);
    for (int i = 0; i < n; ++i) {
      if (!in_focus[static_cast<std::size_t>(i)] || !ok0[static_cast<std::size_t>(i)] ||
          !ok1[static_cast<std::size_t>(i)]) {
        continue;
      }
      const Eigen::Vector3d p0 = range * v0.col(i);
      if (options.distance_m > 0.0) {
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<RayAngleCost, 1, 3, 3>(new RayAngleCost(p0, v1.col(i))),
            new ceres::HuberLoss(huber), r, t);
      } else {
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<RayAngleCost, 1, 3>(new RayAngleCost(p0, v1.col(i))),
            new ceres::HuberLoss(huber), r);
      }
      ++out.fit_points;
    }
    if (out.fit_points < 3) {
      return core::Status::Error("projection diff: " + std::to_string(out.fit_points) +
                                 " grid points within the focus radius of " +
                                 std::to_string(out.focus_radius_px) +
                                 " px unproject in both models (need 3): widen the focus radius");
    }
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    // The residual is ~ angle^2, so its Jacobian vanishes at a perfect fit
    // and the steps shrink geometrically: many cheap iterations, tight
    // tolerances (mrcal sets its gradient tolerance to machine epsilon).
    solver.max_num_iterations = 500;
    solver.function_tolerance = 1e-16;
    solver.gradient_tolerance = 1e-30;
    solver.parameter_tolerance = 1e-14;
    solver.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    if (!summary.IsSolutionUsable()) {
      return core::Status::Error("projection diff: the fit of the frames failed: " +
                                 summary.message);
    }
  }
  ceres::AngleAxisToRotationMatrix(r, ceres::ColumnMajorAdapter3x3(out.R10.data()));
  out.t10 = Eigen::Vector3d(t[0], t[1], t[2]);

  out.q0.resize(static_cast<std::size_t>(n));
  out.difference_px.resize(static_cast<std::size_t>(n));
  out.length_px.resize(static_cast<std::size_t>(n));
  std::vector<double> focus, imager;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    out.q0[k] = pixels.col(i);
    out.difference_px[k] = Eigen::Vector2d(nan, nan);
    out.length_px[k] = nan;
    if (!ok0[k]) continue;
    const core::Result<Eigen::Vector2d> q1 =
        model1.Project(out.R10 * (range * v0.col(i)) + out.t10);
    if (!q1.ok()) continue;
    out.difference_px[k] = *q1 - pixels.col(i);
    out.length_px[k] = out.difference_px[k].norm();
    imager.push_back(out.length_px[k]);
    if (in_focus[k]) focus.push_back(out.length_px[k]);
  }
  out.focus_median_px = core::Median(focus);
  out.focus_max_px = Max(focus);
  out.imager_median_px = core::Median(imager);
  out.imager_max_px = Max(imager);
  return out;
}

cv::Mat RenderProjectionDiff(const ProjectionDiff& diff, int width_px, int height_px,
                             double max_px) {
  assert(max_px > 0.0 && width_px > 0 && height_px > 0);
  // The grid as an image, interpolated over the imager.
  cv::Mat grid(diff.grid_height, diff.grid_width, CV_32F);
  cv::Mat missing(diff.grid_height, diff.grid_width, CV_8U);
  for (int iy = 0; iy < diff.grid_height; ++iy) {
    for (int ix = 0; ix < diff.grid_width; ++ix) {
      const double v = diff.length_px[static_cast<std::size_t>(iy * diff.grid_width + ix)];
      grid.at<float>(iy, ix) = std::isfinite(v) ? static_cast<float>(v) : 0.0f;
      missing.at<std::uint8_t>(iy, ix) = std::isfinite(v) ? 0 : 255;
    }
  }
  cv::Mat values, holes;
  cv::resize(grid, values, cv::Size(width_px, height_px), 0, 0, cv::INTER_LINEAR);
  cv::resize(missing, holes, cv::Size(width_px, height_px), 0, 0, cv::INTER_NEAREST);
  cv::Mat scaled;
  values.convertTo(scaled, CV_8U, 255.0 / max_px);  // saturates above max_px
  cv::Mat colour;
  cv::applyColorMap(scaled, colour, cv::COLORMAP_VIRIDIS);
  colour.setTo(cv::Scalar(128, 128, 128), holes);
  if (diff.focus_radius_px > 0.0) {
    cv::circle(colour, cv::Point((width_px - 1) / 2, (height_px - 1) / 2),
               static_cast<int>(std::lround(diff.focus_radius_px)), cv::Scalar(255, 255, 255), 1,
               cv::LINE_AA);
  }
  // The scale bar: 0 .. max_px, with three labels.
  const int bar_h = 14, label_h = 22;
  cv::Mat canvas(height_px + bar_h + label_h + 8, width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  colour.copyTo(canvas(cv::Rect(0, 0, width_px, height_px)));
  cv::Mat ramp(1, width_px, CV_8U);
  for (int x = 0; x < width_px; ++x) {
    ramp.at<std::uint8_t>(0, x) = static_cast<std::uint8_t>(255 * x / std::max(1, width_px - 1));
  }
  cv::Mat ramp_colour;
  cv::applyColorMap(ramp, ramp_colour, cv::COLORMAP_VIRIDIS);
  cv::resize(ramp_colour, canvas(cv::Rect(0, height_px + 4, width_px, bar_h)),
             cv::Size(width_px, bar_h), 0, 0, cv::INTER_NEAREST);
  for (const double f : {0.0, 0.5, 1.0}) {
    char text[48];
    std::snprintf(text, sizeof text, f == 1.0 ? ">= %.2g px" : "%.2g px", f * max_px);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline);
    const int x =
        std::clamp(static_cast<int>(f * width_px) - size.width / 2, 2, width_px - size.width - 2);
    cv::putText(canvas, text, cv::Point(x, height_px + 4 + bar_h + 16), cv::FONT_HERSHEY_SIMPLEX,
                0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  return canvas;
}

}  // namespace groundline::calibration
