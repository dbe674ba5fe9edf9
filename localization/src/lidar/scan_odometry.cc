#include "groundline/localization/lidar/scan_odometry.h"

#include <Eigen/Eigenvalues>
#include <cassert>
#include <limits>

#include "groundline/localization/relative_pose_factor.h"

namespace groundline::localization::lidar {
namespace {

// Variance given to a direction a scan does not constrain [m^2 or rad^2].
constexpr double kNullVariance = 1e6;

// A covariance from the kept part S^T S of a match's information: the
// inverse on its range, kNullVariance on its null space.
core::Matrix3 CovarianceOf(const MatchInformation& information) {
  const core::Matrix3 kept =
      information.sqrt_information.transpose() * information.sqrt_information;
  Eigen::SelfAdjointEigenSolver<core::Matrix3> eig(kept);
  core::Vector3 variances;
  for (int k = 0; k < 3; ++k) {
    const double lambda = eig.eigenvalues()(k);
    variances(k) = lambda > 1.0 / kNullVariance ? 1.0 / lambda : kNullVariance;
  }
  return eig.eigenvectors() * variances.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

LidarSlamOptions ScanOdometryOptions::DefaultSlam() {
  LidarSlamOptions slam;
  slam.odometry_noise = OdometryNoiseParams();
  slam.loop_search_every_n_nodes = std::numeric_limits<int>::max();  // node 0 only: no loops
  return slam;
}

core::Status ScanOdometryOptions::Validate() const {
  if (core::Status s = slam.Validate(); !s.ok()) return s;
  if (!(information_scale > 0.0 && min_relative_information >= 0.0)) {
    return core::Status::Error(
        "ScanOdometryOptions: need information_scale > 0 and min_relative_information >= 0");
  }
  return core::Status::Ok();
}

core::Matrix3 RelativeInformation(const core::SE2& T_prev_curr, const MatchInformation& previous,
                                  const MatchInformation& current) {
  const core::Matrix3 A = T_prev_curr.Inverse().Adjoint();
  const core::Matrix3 covariance =
      A * CovarianceOf(previous) * A.transpose() + CovarianceOf(current);
  core::Matrix3 information = covariance.inverse();
  return 0.5 * (information + information.transpose());
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
  if (previous_ && previous_->matched && out.matched && out.scans_since_previous > 0) {
    const core::SE2 T_prev_curr = previous_->T_odom_base.Between(out.T_odom_base);
    const core::Matrix3 information =
        options_.information_scale *
        RelativeInformation(T_prev_curr, previous_->information, out.information);
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
