#include "groundline/sim/floor_drive.h"

#include <cassert>
#include <cmath>

#include "groundline/core/random_draws.h"

namespace groundline::sim {

FloorDrive::FloorDrive(const core::FloorMap& map, core::Trajectory trajectory,
                       const FloorDriveOptions& options)
    : options_(options),
      trajectory_(std::move(trajectory)),
      observer_(map,
                [&] {
                  FloorObservationOptions o = options.observations;
                  o.seed = options.seed * 2654435761u + 17u;
                  return o;
                }()),
      integrator_(localization::DiffDriveParams(), options.noise),
      selector_(options.keyframes),
      rng_(options.seed) {
  assert(trajectory_.size() >= 2);
  const double step_s = trajectory_[1].stamp_s - trajectory_[0].stamp_s;
  loop_duration_s_ = trajectory_.back().stamp_s - trajectory_.front().stamp_s + step_s;
}

bool FloorDrive::Next(
    DriveKeyframe* keyframe,
    const std::function<void(double, const localization::RelativeMotion&)>& on_step) {
  std::normal_distribution<double> normal(0.0, 1.0);
  while (true) {
    const size_t next = index_ + 1 == trajectory_.size() ? 0 : index_ + 1;
    if (next == 0 && loop_ + 1 >= options_.loops) return false;
    const core::SE2 delta = trajectory_[index_].pose.Between(trajectory_[next].pose);
    const double true_ds = delta.x();
    const double true_dtheta = delta.yaw();
    const double ds = true_ds * (1.0 + options_.distance_scale_error);
    const double dtheta = true_dtheta * (1.0 + options_.rotation_scale_error);
    localization::OdometryIncrement increment;
    increment.covariance = localization::IncrementCovariance(options_.noise, ds, dtheta);
    const Eigen::Vector3d noise =
        increment.covariance.diagonal().cwiseSqrt().cwiseProduct(core::DrawVector<3>(normal, rng_));
    // The odometry reports the nominal arc; the truth differs from it by the noise.
    increment.T_prev_curr =
        core::SE2::Exp(Eigen::Vector3d(ds, 0.0, dtheta)) * core::SE2::Exp(-noise);
    increment.distance_m = ds;
    increment.rotation_rad = dtheta;
    integrator_.Integrate(increment);
    if (next == 0) ++loop_;
    index_ = next;
    const double stamp_s = trajectory_[index_].stamp_s + loop_ * loop_duration_s_;
    if (on_step) on_step(stamp_s, integrator_.SinceKeyframe());
    if (!selector_.IsKeyframeDue(integrator_.SinceKeyframe().T_start_end)) continue;
    keyframe->stamp_s = stamp_s;
    keyframe->T_map_base_true = trajectory_[index_].pose;
    keyframe->motion = integrator_.StartKeyframe();
    keyframe->observations = observer_.Observe(stamp_s, keyframe->T_map_base_true);
    return true;
  }
}

}  // namespace groundline::sim
