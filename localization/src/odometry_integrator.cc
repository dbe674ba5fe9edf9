#include "groundline/localization/odometry_integrator.h"

#include <cassert>
#include <cmath>

namespace groundline::localization {

OdometryIntegrator::OdometryIntegrator(const DiffDriveParams& drive,
                                       const OdometryNoiseParams& noise)
    : drive_(drive), noise_(noise) {
  assert(drive_.Validate().ok());
  assert(noise_.Validate().ok());
}

void OdometryIntegrator::Reset(const core::SE2& T_odom_base, const core::Matrix3& covariance) {
  since_reset_ = RelativeMotion{};
  since_reset_.T_start_end = T_odom_base;
  since_reset_.covariance = covariance;
  since_keyframe_ = RelativeMotion{};
}

OdometryIncrement OdometryIntegrator::Integrate(const WheelAngleIncrement& wheels) {
  const OdometryIncrement increment = IncrementFromWheels(drive_, noise_, wheels);
  Integrate(increment);
  return increment;
}

void OdometryIntegrator::Integrate(const OdometryIncrement& increment) {
  assert(increment.covariance.isApprox(increment.covariance.transpose()));
  Accumulate(increment, &since_reset_);
  Accumulate(increment, &since_keyframe_);
}

RelativeMotion OdometryIntegrator::StartKeyframe() {
  const RelativeMotion span = since_keyframe_;
  since_keyframe_ = RelativeMotion{};
  return span;
}

void OdometryIntegrator::Accumulate(const OdometryIncrement& increment, RelativeMotion* motion) {
  core::Matrix3 j_prev;  // Ad(D^-1); the Jacobian with respect to D is I
  motion->T_start_end = motion->T_start_end.Compose(increment.T_prev_curr, &j_prev);
  motion->covariance = j_prev * motion->covariance * j_prev.transpose() + increment.covariance;
  // Keep it exactly symmetric so that round-off does not accumulate.
  motion->covariance = 0.5 * (motion->covariance + motion->covariance.transpose()).eval();
  motion->path_length_m += std::abs(increment.distance_m);
  motion->rotation_rad += std::abs(increment.rotation_rad);
  ++motion->num_increments;
}

}  // namespace groundline::localization
