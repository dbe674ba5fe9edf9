// Shared helpers of the wheel-encoder simulator tests: feasible truth paths
// built from arcs, dead reckoning of a simulated log, and the integrator
// noise that covers the simulator's error model.
#ifndef GROUNDLINE_TESTS_SIM_ENCODER_TEST_PATHS_H_
#define GROUNDLINE_TESTS_SIM_ENCODER_TEST_PATHS_H_

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "groundline/core/trajectory.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/sim/wheel_encoders.h"
#include "test_units.h"

namespace groundline::sim::testing {

using core::SE2;
using core::Vector3;
using localization::DiffDriveParams;
using localization::OdometryIntegrator;
using localization::OdometryNoiseParams;
using ::groundline::testing::kPi;

struct Segment {
  double distance_m;
  double rotation_rad;
  int steps;
};

// A warehouse-like run at 1 m/s: down an aisle, U-turn into the next aisle,
// back, turn in place, reverse into a station. About 20.7 m and 4.7 rad, in
// steps of 1 cm / 1 degree (encoders read at 100 Hz) times `coarsen`.
inline std::vector<Segment> WarehouseRun(int coarsen = 1) {
  return {{8.0, 0.0, 800 / coarsen},
          {1.5 * kPi, kPi, 471 / coarsen},
          {8.0, 0.0, 800 / coarsen},
          {0.0, -kPi / 2.0, 90 / coarsen},
          {-2.0, 0.0, 200 / coarsen}};
}

inline core::Trajectory TruthFromSegments(const std::vector<Segment>& segments,
                                          double rate_hz = 100.0) {
  core::Trajectory truth{{0.0, SE2(1.0, 2.0, 0.3), std::nullopt}};
  for (const Segment& s : segments) {
    const SE2 step = SE2::Exp(Vector3(s.distance_m / s.steps, 0.0, s.rotation_rad / s.steps));
    for (int i = 0; i < s.steps; ++i) {
      truth.push_back({truth.back().stamp_s + 1.0 / rate_hz, truth.back().pose * step, {}});
    }
  }
  return truth;
}

// Dead-reckons the readings from the first truth pose; one pose per reading.
inline std::vector<SE2> DeadReckon(const WheelEncoderLog& log, const SE2& start,
                                   const DiffDriveParams& drive, const OdometryNoiseParams& noise,
                                   core::Matrix3* final_covariance = nullptr) {
  OdometryIntegrator odometry(drive, noise);
  odometry.Reset(start);
  std::vector<SE2> poses;
  for (const EncoderReading& r : log.readings) {
    odometry.Integrate(r.increment);
    poses.push_back(odometry.T_odom_base());
  }
  if (final_covariance != nullptr) *final_covariance = odometry.covariance();
  return poses;
}

// Integrator noise that covers the simulator's error model over a run in
// which each wheel travels at most `wheel_travel_m`:
// - random travel error: per-wheel variance rate q (OdometryNoiseFromWheelVariance);
// - radius scale error e ~ N(0, s^2): systematic, so its variance grows with the
//   square of the distance, (s d)^2. A random walk with rate s^2 * D has the same
//   variance s^2 D^2 at distance D; with D the longest wheel travel it covers the
//   final along-track and heading errors, and the lateral error the heading error
//   drives (random walk: k_theta_d L^3 / 3 >= bias: s^2 L^4 / (2 B^2)).
// So q_eff = q + s^2 * wheel_travel_m. The simulator has no lateral error
// source; k_lat only keeps the covariance invertible.
inline OdometryNoiseParams CoveringNoise(const WheelEncoderOptions& sim, double track_m,
                                         double wheel_travel_m) {
  const double q_eff = sim.wheel_variance_m2_per_m +
                       sim.radius_scale_stddev * sim.radius_scale_stddev * wheel_travel_m;
  return localization::OdometryNoiseFromWheelVariance(q_eff, track_m, 1e-8);
}

inline double MaxWheelTravel(const core::Trajectory& truth, const DiffDriveParams& drive) {
  double left_m = 0.0, right_m = 0.0;
  for (size_t k = 1; k < truth.size(); ++k) {
    const Vector3 step = truth[k - 1].pose.Between(truth[k].pose).Log();
    left_m += std::abs(step.x() - 0.5 * drive.track_m * step.z());
    right_m += std::abs(step.x() + 0.5 * drive.track_m * step.z());
  }
  return std::max(left_m, right_m);
}

}  // namespace groundline::sim::testing

#endif  // GROUNDLINE_TESTS_SIM_ENCODER_TEST_PATHS_H_
