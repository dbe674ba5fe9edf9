// Dead reckoning: accumulates odometry increments into T_odom_base with its
// covariance, and the motion since the last keyframe (the measurement of an
// odometry between-factor) with its own covariance.
//
// Propagation (first order, right perturbations, docs/conventions.md): with
// T' = T * D,
//   Sigma_T' = J_a Sigma_T J_a^T + J_b Sigma_D J_b^T,
//   J_a = d(T*D)/dT = Ad(D^-1),  J_b = d(T*D)/dD = I   (SE2::Compose).
// Increments are treated as independent, so the motion since a keyframe and
// its covariance are accumulated from identity in the same way and do not
// depend on what happened before the keyframe.
//
// Not thread-safe; one integrator per odometry stream.
#ifndef GROUNDLINE_LOCALIZATION_ODOMETRY_INTEGRATOR_H_
#define GROUNDLINE_LOCALIZATION_ODOMETRY_INTEGRATOR_H_

#include "groundline/core/se2.h"
#include "groundline/localization/diff_drive_odometry.h"

namespace groundline::localization {

// Accumulated motion over a span of readings.
struct RelativeMotion {
  // Pose of base_link at the end of the span in base_link at its start.
  core::SE2 T_start_end;
  // Covariance of T_start_end (tangent space, right perturbation, (x, y, yaw)).
  core::Matrix3 covariance = core::Matrix3::Zero();
  double path_length_m = 0.0;  // sum of |ds|
  double rotation_rad = 0.0;   // sum of |dtheta|
  int num_increments = 0;
};

class OdometryIntegrator {
 public:
  // Both parameter structs must be valid (asserted). Starts at identity with
  // zero covariance and a keyframe there.
  OdometryIntegrator(const DiffDriveParams& drive, const OdometryNoiseParams& noise);

  // Restarts at T_odom_base with the given covariance; the keyframe span
  // restarts there too.
  void Reset(const core::SE2& T_odom_base = core::SE2(),
             const core::Matrix3& covariance = core::Matrix3::Zero());

  // Converts one encoder reading and accumulates it; returns the increment.
  OdometryIncrement Integrate(const WheelAngleIncrement& wheels);
  // Accumulates an increment from elsewhere (its covariance must be symmetric PSD).
  void Integrate(const OdometryIncrement& increment);

  const core::SE2& T_odom_base() const { return since_reset_.T_start_end; }
  // Covariance of T_odom_base (includes the covariance given to Reset).
  const core::Matrix3& covariance() const { return since_reset_.covariance; }
  // Everything accumulated since Reset (T_start_end = T_odom_base).
  const RelativeMotion& since_reset() const { return since_reset_; }

  // Motion since the last keyframe (T_start_end = T_keyframe_base).
  const RelativeMotion& SinceKeyframe() const { return since_keyframe_; }
  // Returns SinceKeyframe() and starts a new keyframe span at the current pose.
  RelativeMotion StartKeyframe();

  const DiffDriveParams& drive() const { return drive_; }
  const OdometryNoiseParams& noise() const { return noise_; }

 private:
  static void Accumulate(const OdometryIncrement& increment, RelativeMotion* motion);

  DiffDriveParams drive_;
  OdometryNoiseParams noise_;
  RelativeMotion since_reset_;
  RelativeMotion since_keyframe_;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_ODOMETRY_INTEGRATOR_H_
