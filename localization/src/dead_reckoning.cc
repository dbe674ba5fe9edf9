#include "groundline/localization/dead_reckoning.h"

#include <cmath>
#include <string>

#include "groundline/localization/odometry_integrator.h"

namespace groundline::localization {

core::Status DeadReckoningOptions::Validate() const {
  if (core::Status s = drive.Validate(); !s.ok()) return s.WithContext("drive");
  if (core::Status s = noise.Validate(); !s.ok()) return s.WithContext("noise");
  if (core::Status s = keyframes.Validate(); !s.ok()) return s.WithContext("keyframes");
  return core::Status::Ok();
}

core::Result<DeadReckoningResult> DeadReckon(const std::vector<core::WheelEncoderReading>& readings,
                                             const core::StampedPose& initial,
                                             const DeadReckoningOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s.WithContext("dead reckoning options");
  const core::Matrix3 initial_covariance = initial.covariance.value_or(core::Matrix3::Zero());
  OdometryIntegrator integrator(options.drive, options.noise);
  integrator.Reset(core::SE2(), initial_covariance);
  const KeyframeSelector selector(options.keyframes);

  DeadReckoningResult result;
  core::StampedPose first{initial.stamp_s, initial.pose, initial_covariance};
  result.odometry_rate.push_back(first);
  result.keyframes.push_back(first);

  double previous_stamp_s = initial.stamp_s;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const core::WheelEncoderReading& r = readings[i];
    if (!std::isfinite(r.stamp_s) || !std::isfinite(r.left_delta_rad) ||
        !std::isfinite(r.right_delta_rad)) {
      return core::Status::Error("wheel encoder reading " + std::to_string(i) +
                                 ": expected finite stamp and wheel increments");
    }
    if (r.stamp_s <= initial.stamp_s) continue;
    if (!(r.stamp_s > previous_stamp_s)) {
      return core::Status::Error("wheel encoder reading " + std::to_string(i) +
                                 ": stamps must increase strictly");
    }
    previous_stamp_s = r.stamp_s;
    integrator.Integrate(WheelAngleIncrement{r.left_delta_rad, r.right_delta_rad});
    const core::StampedPose pose{r.stamp_s, initial.pose * integrator.T_odom_base(),
                                 integrator.covariance()};
    result.odometry_rate.push_back(pose);
    if (selector.IsKeyframeDue(integrator.SinceKeyframe().T_start_end)) {
      integrator.StartKeyframe();
      result.keyframes.push_back(pose);
    }
  }
  result.path_length_m = integrator.since_reset().path_length_m;
  return result;
}

}  // namespace groundline::localization
