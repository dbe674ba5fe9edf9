#include "groundline/localization/lidar/scan_odometry.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "groundline/localization/relative_pose_factor.h"

namespace groundline::localization::lidar {
namespace {

// Two null directions closer than this (sine of their angle, ~10 deg) are
// one: the noisy weakest directions of two matches in one corridor.
constexpr double kSameNullSine = 0.17;

// The pseudo-inverse of a match's kept information S^T S (its covariance on
// the constrained directions, zero on the others) and its unit null directions.
core::Matrix3 KeptCovariance(const core::Matrix3& sqrt_information,
                             std::vector<core::Vector3>* nulls) {
  const core::Matrix3 kept = sqrt_information.transpose() * sqrt_information;
  Eigen::SelfAdjointEigenSolver<core::Matrix3> eig(kept);
  const double tiny = 1e-9 * std::max(1.0, eig.eigenvalues()(2));
  core::Matrix3 covariance = core::Matrix3::Zero();
  for (int k = 0; k < 3; ++k) {
    const core::Vector3 v = eig.eigenvectors().col(k);
    if (eig.eigenvalues()(k) > tiny) {
      covariance += v * v.transpose() / eig.eigenvalues()(k);
    } else {
      nulls->push_back(v);
    }
  }
  return covariance;
}

}  // namespace

LidarSlamOptions ScanOdometryOptions::DefaultSlam() {
  LidarSlamOptions slam;
  slam.odometry_noise = OdometryNoiseParams();
  slam.loop_search_every_n_nodes = std::numeric_limits<int>::max();  // node 0 only: no loops
  slam.retain_finished_submaps = false;  // no loops: memory stays flat over a shift
  // A poor match is retried near the odometry's prediction only: a
  // calibrated AGV's wheels are not a log's stale odometry, and in an aisle
  // or at an aisle's corner, which look alike turned by 90 or 180 deg, a
  // search over every heading finds the scan turned.
  slam.recovery_search.linear_window_m = 0.3;
  slam.recovery_search.angular_window_rad = 0.1;
  // Per scan (15 Hz) the wheels are off by millimetres, a slip by a few
  // centimetres; a larger correction is a scan that does not see the submap.
  slam.max_match_correction_m = 0.1;
  slam.max_match_correction_rad = 0.05;
  return slam;
}

core::Status ScanOdometryOptions::Validate() const {
  if (core::Status s = slam.Validate(); !s.ok()) return s;
  if (core::Status s = aliasing.Validate(); !s.ok()) return s;
  if (!(information_scale > 0.0 && min_relative_information >= 0.0)) {
    return core::Status::Error(
        "ScanOdometryOptions: need information_scale > 0 and min_relative_information >= 0");
  }
  return core::Status::Ok();
}

core::Matrix3 RelativeInformation(const core::SE2& T_prev_curr, const core::Matrix3& previous,
                                  const core::Matrix3& current) {
  // Z = T_prev^-1 T_curr: a right perturbation xi of T_prev moves Z by
  // -Ad(Z^-1) xi, one of T_curr by itself.
  const core::Matrix3 A = T_prev_curr.Inverse().Adjoint();
  std::vector<core::Vector3> prev_nulls, nulls;
  const core::Matrix3 prev_covariance = KeptCovariance(previous, &prev_nulls);
  const core::Matrix3 covariance =
      A * prev_covariance * A.transpose() + KeptCovariance(current, &nulls);
  for (const core::Vector3& v : prev_nulls) nulls.push_back((A * v).normalized());
  // The unconstrained subspace: the span of both matches' null directions,
  // nearly parallel ones merged.
  core::Matrix3 projector = core::Matrix3::Identity();  // onto the constrained directions
  if (!nulls.empty()) {
    Eigen::Matrix<double, 3, Eigen::Dynamic> M(3, static_cast<int>(nulls.size()));
    for (std::size_t k = 0; k < nulls.size(); ++k) M.col(static_cast<int>(k)) = nulls[k];
    Eigen::JacobiSVD<Eigen::Matrix<double, 3, Eigen::Dynamic>> svd(M, Eigen::ComputeFullU);
    for (int k = 0; k < static_cast<int>(svd.singularValues().size()); ++k) {
      if (svd.singularValues()(k) < kSameNullSine) continue;
      const core::Vector3 u = svd.matrixU().col(k);
      projector -= u * u.transpose();
    }
  }
  // The information on the constrained directions: the inverse of the
  // covariance restricted to them.
  const core::Matrix3 restricted = projector * covariance * projector;
  Eigen::SelfAdjointEigenSolver<core::Matrix3> eig(0.5 * (restricted + restricted.transpose()));
  const double tiny = 1e-12 * std::max(1e-12, eig.eigenvalues()(2));
  core::Matrix3 information = core::Matrix3::Zero();
  for (int k = 0; k < 3; ++k) {
    const core::Vector3 v = eig.eigenvectors().col(k);
    if (eig.eigenvalues()(k) > tiny && (projector * v).norm() > 0.5) {
      information += v * v.transpose() / eig.eigenvalues()(k);
    }
  }
  return information;
}

double MidSweepOffsetS(std::size_t num_rays, double angle_increment_rad, double rate_hz) {
  assert(rate_hz > 0.0);
  if (num_rays < 2) return 0.0;
  const double per_ray_s = std::abs(angle_increment_rad) / (2.0 * std::numbers::pi * rate_hz);
  return 0.5 * static_cast<double>(num_rays - 1) * per_ray_s;
}

ScanOdometry::ScanOdometry(const ScanOdometryOptions& options)
    : options_(options), slam_([&] {
        assert(options.Validate().ok());
        return options.slam;
      }()) {}

core::Result<ScanReport> ScanOdometry::AddScan(double stamp_s, const core::SE2& T_odom_base,
                                               const ScanPoints& scan) {
  if (num_scans_ == 0) T_odom_local_ = T_odom_base;
  core::Result<ScanReport> report = slam_.AddScan(stamp_s, T_odom_base, scan);
  if (!report.ok()) return report;
  last_odom_ = T_odom_base;
  last_local_ = report->T_local_base;
  last_report_ = *report;
  last_scan_ = scan;
  ++num_scans_;
  ++scans_since_keyframe_;
  return report;
}

ScanOdometryKeyframe ScanOdometry::Keyframe(double stamp_s, const core::SE2& T_odom_base) {
  ScanOdometryKeyframe out;
  out.stamp_s = stamp_s;
  out.scans_since_previous = scans_since_keyframe_;
  scans_since_keyframe_ = 0;
  if (num_scans_ == 0) {
    out.T_odom_base = T_odom_base;
    out.information.degenerate = true;
    previous_ = out;
    return out;
  }
  out.T_odom_base = T_odom_local_ * last_local_ * last_odom_.Between(T_odom_base);
  out.matched = last_report_.matched;
  out.match_score = last_report_.match.score;
  out.information = last_report_.information;
  out.sqrt_information_kept = out.information.sqrt_information;
  if (options_.check_aliasing) {
    out.aliasing = DetectScanAliasing(last_scan_, out.information, options_.aliasing);
    if (out.aliasing.aliased) {
      out.sqrt_information_kept =
          RemoveTranslation(out.sqrt_information_kept, out.aliasing.direction);
    }
  }
  out.degenerate = out.information.degenerate || out.aliasing.aliased;
  if (previous_ && previous_->matched && out.matched && out.scans_since_previous > 0) {
    const core::SE2 T_prev_curr = previous_->T_odom_base.Between(out.T_odom_base);
    const core::Matrix3 information =
        options_.information_scale * RelativeInformation(T_prev_curr,
                                                         previous_->sqrt_information_kept,
                                                         out.sqrt_information_kept);
    core::Result<core::Matrix3> sqrt_information =
        SqrtInformation(information, options_.min_relative_information);
    if (sqrt_information.ok()) {
      for (int r = 0; r < 3; ++r) out.relative_rank += sqrt_information->row(r).norm() > 0.0;
      if (out.relative_rank > 0)
        out.relative = RelativePoseMeasurement{T_prev_curr, *sqrt_information};
    }
  }
  previous_ = out;
  return out;
}

}  // namespace groundline::localization::lidar
