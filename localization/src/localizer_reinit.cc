// Re-initialization of a running localizer (Localizer::SetInitialPose after
// the start): the time rules and the restart of the estimate.
#include <algorithm>
#include <string>

#include "groundline/core/trajectory_association.h"
#include "localizer_impl.h"

namespace groundline::localization::internal {
namespace {

// The wheel odometry at stamp_s inside the history (stamps increasing):
// the pose interpolated, the covariance of the reading at or after it (the
// integrator's covariance only grows between readings).
PoseEstimate OdometryAt(const std::deque<PoseEstimate>& history, double stamp_s) {
  const auto it = std::lower_bound(history.begin(), history.end(), stamp_s,
                                   [](const PoseEstimate& p, double t) { return p.stamp_s < t; });
  if (it == history.begin()) return *it;
  if (it == history.end()) return history.back();
  const PoseEstimate& a = *(it - 1);
  const double f = (stamp_s - a.stamp_s) / (it->stamp_s - a.stamp_s);
  return {stamp_s, core::InterpolateSE2(a.T_map_base, it->T_map_base, f), it->covariance};
}

}  // namespace

core::Status LocalizerImpl::Restart(const PoseEstimate& given) {
  if (given.stamp_s > current.stamp_s + kSameInstantS) {
    // Ahead of the odometry (within max_sensor_lead_s, SetInitialPose): it
    // waits for the reading that reaches its time; the newest call wins.
    if (pending_pose) ++counters.initial_poses_superseded;
    pending_pose = given;
    return core::Status::Ok();
  }
  if (given.stamp_s < odometry_history.front().stamp_s - kSameInstantS) {
    ++counters.initial_poses_dropped_late;
    return core::Status::Error(
        "initial pose: stamped " + std::to_string(current.stamp_s - given.stamp_s) +
        " s before the newest wheel reading, before the odometry kept since the start or the "
        "last re-initialization (odometry_history_s " +
        std::to_string(options.odometry_history_s) +
        "): too old to carry forward; dropped (send it again stamped now)");
  }
  if (pending_pose) {
    ++counters.initial_poses_superseded;  // this one came later
    pending_pose.reset();
  }
  Reinitialize(given);
  return core::Status::Ok();
}

void LocalizerImpl::Reinitialize(const PoseEstimate& given) {
  pending_pose.reset();
  const double now_s = current.stamp_s;
  // The wheel odometry from the given stamp to now: D = T_then^-1 T_now, and
  // its own covariance from the integrator's (Sigma_now = Ad(D^-1)
  // Sigma_then Ad(D^-1)^T + Sigma_D, odometry_integrator.h).
  const PoseEstimate then = OdometryAt(odometry_history, given.stamp_s);
  const core::SE2 D = then.T_map_base.Between(odometry->T_odom_base());
  const core::Matrix3 Ad = D.Inverse().Adjoint();
  core::Matrix3 covariance = Ad * given.covariance * Ad.transpose() + odometry->covariance() -
                             Ad * then.covariance * Ad.transpose();
  covariance = 0.5 * (covariance + covariance.transpose()).eval();
  const core::SE2 T_map_base = given.T_map_base * D;

  if (smoother) {
    // The window restarts at now, its prior the given pose; the odometry's
    // next between-factor starts here too.
    odometry->StartKeyframe();
    smoother->Initialize(now_s, T_map_base, covariance);
  } else {
    // Dead reckoning carries the new pose's covariance from here; the odom
    // frame goes on (the LiDAR stage's history interpolates across now).
    const core::SE2 T_odom_base = odometry->T_odom_base();  // Reset clears what it refers to
    odometry->Reset(T_odom_base, covariance);
  }
  T_reinit = T_map_base * (T_map_start * odometry->T_odom_base()).Inverse();
  keyframe = {now_s, T_map_base, covariance};
  T_odom_keyframe = DeadReckoning();
  if (lidar) lidar->Renew(now_s, T_map_base);
  // What came before belongs to the old estimate: PoseAt and a later
  // re-initialization start from here.
  history.clear();
  odometry_history.clear();
  UpdateCurrent(now_s);
  ++counters.reinitializations;
}

}  // namespace groundline::localization::internal
