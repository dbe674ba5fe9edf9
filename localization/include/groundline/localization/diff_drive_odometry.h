// Differential-drive wheel odometry: one encoder reading (left and right
// wheel angle increments) -> one SE(2) motion increment of base_link and its
// covariance. Forward kinematics and noise model after the seed paper,
// section 3.2 (eqs. 6-9); frames, tangent order and covariance convention as
// in docs/conventions.md.
//
// Kinematics (eqs. 6-7), wheel angles in rad, positive = driving forward:
//   ds     = r/2 (dphi_R + dphi_L)        arc length of the axle midpoint [m]
//   dtheta = r/B (dphi_R - dphi_L)        heading change, counter-clockwise [rad]
// Within one reading both wheels are assumed to turn at constant rates, so
// base_link follows a circular arc and the increment is exactly
//   T_prev_curr = Exp((ds, 0, dtheta)).
// (The paper scales ds by sinc(dtheta/2) inside Exp; that is the chord length,
// which belongs to a straight-chord model, not to Exp. Exp of the arc length
// is the exact arc.)
//
// Noise (eq. 9), a right perturbation of the increment:
//   T_true = T_prev_curr * Exp(w),  w ~ N(0, diag(s_s^2, s_lat^2, s_theta^2))
//   s_s^2     = k_d |ds| + k_d_theta |dtheta|
//   s_lat^2   = k_lat |ds|
//   s_theta^2 = k_theta |dtheta| + k_theta_d |ds|
// The paper reuses k_d and k_theta for the cross terms, which adds m^2 to
// rad^2; here each term has its own coefficient so the units are consistent.
// The paper puts w inside the Exp (Exp(xi + w)); the two differ by Jr(xi),
// which is I to first order in the step size.
#ifndef GROUNDLINE_LOCALIZATION_DIFF_DRIVE_ODOMETRY_H_
#define GROUNDLINE_LOCALIZATION_DIFF_DRIVE_ODOMETRY_H_

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::localization {

// Geometry of a differential drive. The kinematics above take each wheel
// with its own radius: r_L dphi_L and r_R dphi_R are the wheels' travels,
//   ds = (r_R dphi_R + r_L dphi_L) / 2,  dtheta = (r_R dphi_R - r_L dphi_L) / B.
struct DiffDriveParams {
  double wheel_radius_m = 0.125;  // nominal radius of both drive wheels
  double track_m = 0.760;         // distance between the wheel contact points (B)
  // Calibrated effective radii (odometry_calibration.h); 0: wheel_radius_m.
  // Tyre wear and load make them differ from the nominal and from each other
  // by tenths of a percent: on a 100 m aisle, 0.2 % is 20 cm along the track,
  // and a 0.1 % left-right difference turns the heading by 7.5 degrees.
  double left_wheel_radius_m = 0.0;
  double right_wheel_radius_m = 0.0;

  double LeftRadius() const {
    return left_wheel_radius_m > 0.0 ? left_wheel_radius_m : wheel_radius_m;
  }
  double RightRadius() const {
    return right_wheel_radius_m > 0.0 ? right_wheel_radius_m : wheel_radius_m;
  }
  // Ok if wheel_radius_m and track_m are finite and > 0 and the per-wheel
  // radii finite and >= 0; otherwise names the field and the value.
  core::Status Validate() const;
};

// Variance rates of the increment noise (see the formulas above). The
// defaults correspond to OdometryNoiseFromWheelVariance(2e-4, 0.760, 1e-5):
// a wheel whose travel has a standard deviation of 1.4 cm per metre. Calibrate
// them on the vehicle.
struct OdometryNoiseParams {
  double k_d = 1.0e-4;        // [m^2/m]     forward variance per metre travelled
  double k_lat = 1.0e-5;      // [m^2/m]     lateral variance per metre travelled
  double k_theta = 2.6e-4;    // [rad^2/rad] heading variance per radian turned
  double k_theta_d = 6.9e-4;  // [rad^2/m]   heading variance per metre travelled
  double k_d_theta = 3.8e-5;  // [m^2/rad]   forward variance per radian turned

  // Ok if all are finite, k_d, k_lat and k_theta are > 0 (so that the
  // accumulated covariance of any motion longer than a point is invertible)
  // and the cross terms are >= 0.
  core::Status Validate() const;
};

// Rates that reproduce, for straight driving and for turning in place, the
// covariance of independent per-wheel errors whose variance grows by
// `wheel_variance_m2_per_m` per metre of that wheel's travel:
//   k_d = q/2, k_theta_d = 2q/B^2, k_theta = q/B, k_d_theta = q B/4, k_lat given.
// On mixed arcs the diagonal model ignores the ds-dtheta correlation of
// (q_R - q_L)/(2B) per metre.
OdometryNoiseParams OdometryNoiseFromWheelVariance(double wheel_variance_m2_per_m, double track_m,
                                                   double k_lat_m2_per_m);

// One encoder reading: how far each wheel turned since the previous reading.
struct WheelAngleIncrement {
  double left_rad = 0.0;
  double right_rad = 0.0;
};

// The motion of base_link over one reading.
struct OdometryIncrement {
  core::SE2 T_prev_curr;  // pose at the end of the step in base_link at its start
  // Covariance of T_prev_curr in its tangent space (right perturbation,
  // (x, y, yaw) order; m^2, rad^2); diagonal.
  core::Matrix3 covariance = core::Matrix3::Zero();
  double distance_m = 0.0;    // signed arc length ds (negative when reversing)
  double rotation_rad = 0.0;  // signed heading change dtheta
};

// Converts one encoder reading into an increment. Both parameter structs
// must be valid (asserted).
OdometryIncrement IncrementFromWheels(const DiffDriveParams& drive,
                                      const OdometryNoiseParams& noise,
                                      const WheelAngleIncrement& wheels);

// The inverse kinematics: wheel angles that drive the arc (ds, dtheta).
WheelAngleIncrement WheelsFromArc(const DiffDriveParams& drive, double distance_m,
                                  double rotation_rad);

// The wheel angles of a planar odometry increment T_prev_curr (e.g. the
// Between of consecutive nav_msgs/Odometry poses): the arc (ds, dtheta) of
// Log(T_prev_curr) = (ds, d_lateral, dtheta), driven by WheelsFromArc. A
// differential drive cannot move sideways, so d_lateral (rounding, or a fused
// odometry source's lateral correction) is dropped; *lateral_m, if given,
// receives it. IncrementFromWheels of the result is Exp((ds, 0, dtheta)).
WheelAngleIncrement WheelsFromIncrement(const DiffDriveParams& drive, const core::SE2& T_prev_curr,
                                        double* lateral_m = nullptr);

// The diagonal covariance of an increment of arc length ds and rotation
// dtheta (eq. 9 above).
core::Matrix3 IncrementCovariance(const OdometryNoiseParams& noise, double distance_m,
                                  double rotation_rad);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_DIFF_DRIVE_ODOMETRY_H_
