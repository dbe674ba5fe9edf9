#include "groundline/localization/diff_drive_odometry.h"

#include <cassert>
#include <cmath>
#include <sstream>
#include <string>

namespace groundline::localization {
namespace {

// "Struct.field: expected <what>, got <value>".
core::Status FieldError(const std::string& field, const std::string& expected, double value) {
  std::ostringstream out;
  out << field << ": expected " << expected << ", got " << value;
  return core::Status::Error(out.str());
}

core::Status RequirePositive(const std::string& field, const std::string& unit, double value) {
  if (std::isfinite(value) && value > 0.0) return core::Status::Ok();
  return FieldError(field, "a finite value > 0 [" + unit + "]", value);
}

core::Status RequireNonNegative(const std::string& field, const std::string& unit, double value) {
  if (std::isfinite(value) && value >= 0.0) return core::Status::Ok();
  return FieldError(field, "a finite value >= 0 [" + unit + "]", value);
}

}  // namespace

core::Status DiffDriveParams::Validate() const {
  if (auto s = RequirePositive("DiffDriveParams.wheel_radius_m", "m", wheel_radius_m); !s.ok()) {
    return s;
  }
  if (auto s = RequirePositive("DiffDriveParams.track_m", "m", track_m); !s.ok()) return s;
  if (auto s = RequireNonNegative("DiffDriveParams.left_wheel_radius_m", "m", left_wheel_radius_m);
      !s.ok()) {
    return s;
  }
  return RequireNonNegative("DiffDriveParams.right_wheel_radius_m", "m", right_wheel_radius_m);
}

core::Status OdometryNoiseParams::Validate() const {
  const struct {
    const char* name;
    const char* unit;
    double value;
    bool may_be_zero;
  } fields[] = {
      {"OdometryNoiseParams.k_d", "m^2/m", k_d, false},
      {"OdometryNoiseParams.k_lat", "m^2/m", k_lat, false},
      {"OdometryNoiseParams.k_theta", "rad^2/rad", k_theta, false},
      {"OdometryNoiseParams.k_theta_d", "rad^2/m", k_theta_d, true},
      {"OdometryNoiseParams.k_d_theta", "m^2/rad", k_d_theta, true},
  };
  for (const auto& f : fields) {
    core::Status s = f.may_be_zero ? RequireNonNegative(f.name, f.unit, f.value)
                                   : RequirePositive(f.name, f.unit, f.value);
    if (!s.ok()) return s;
  }
  return core::Status::Ok();
}

OdometryNoiseParams OdometryNoiseFromWheelVariance(double wheel_variance_m2_per_m, double track_m,
                                                   double k_lat_m2_per_m) {
  assert(wheel_variance_m2_per_m > 0.0 && track_m > 0.0);
  // ds = (d_R + d_L)/2 and dtheta = (d_R - d_L)/B with independent wheel
  // errors of variance q |d_wheel|. Straight (|d_L| = |d_R| = |ds|):
  // var(ds) = q |ds|/2, var(dtheta) = 2 q |ds| / B^2. In place
  // (|d_L| = |d_R| = B |dtheta|/2): var(ds) = q B |dtheta|/4,
  // var(dtheta) = q |dtheta| / B.
  const double q = wheel_variance_m2_per_m;
  const double b = track_m;
  OdometryNoiseParams p;
  p.k_d = q / 2.0;
  p.k_lat = k_lat_m2_per_m;
  p.k_theta = q / b;
  p.k_theta_d = 2.0 * q / (b * b);
  p.k_d_theta = q * b / 4.0;
  return p;
}

core::Matrix3 IncrementCovariance(const OdometryNoiseParams& noise, double distance_m,
                                  double rotation_rad) {
  const double ds = std::abs(distance_m);
  const double dtheta = std::abs(rotation_rad);
  core::Matrix3 cov = core::Matrix3::Zero();
  cov(0, 0) = noise.k_d * ds + noise.k_d_theta * dtheta;
  cov(1, 1) = noise.k_lat * ds;
  cov(2, 2) = noise.k_theta * dtheta + noise.k_theta_d * ds;
  return cov;
}

OdometryIncrement IncrementFromWheels(const DiffDriveParams& drive,
                                      const OdometryNoiseParams& noise,
                                      const WheelAngleIncrement& wheels) {
  assert(drive.Validate().ok());
  assert(noise.Validate().ok());
  const double left_m = drive.LeftRadius() * wheels.left_rad;
  const double right_m = drive.RightRadius() * wheels.right_rad;
  OdometryIncrement inc;
  inc.distance_m = 0.5 * (right_m + left_m);
  inc.rotation_rad = (right_m - left_m) / drive.track_m;
  inc.T_prev_curr = core::SE2::Exp(core::Vector3(inc.distance_m, 0.0, inc.rotation_rad));
  inc.covariance = IncrementCovariance(noise, inc.distance_m, inc.rotation_rad);
  return inc;
}

WheelAngleIncrement WheelsFromArc(const DiffDriveParams& drive, double distance_m,
                                  double rotation_rad) {
  assert(drive.Validate().ok());
  const double half_track_turn_m = 0.5 * drive.track_m * rotation_rad;
  return {(distance_m - half_track_turn_m) / drive.LeftRadius(),
          (distance_m + half_track_turn_m) / drive.RightRadius()};
}

WheelAngleIncrement WheelsFromIncrement(const DiffDriveParams& drive, const core::SE2& T_prev_curr,
                                        double* lateral_m) {
  const core::Vector3 xi = T_prev_curr.Log();
  if (lateral_m != nullptr) *lateral_m = xi.y();
  return WheelsFromArc(drive, xi.x(), xi.z());
}

}  // namespace groundline::localization
