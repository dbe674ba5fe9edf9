// The odometry noise model of `groundline localize` (tools/localize_lines.h:
// wheel variance 1e-5 m^2/m, lateral 1e-7 m^2/m, plus the smoother's
// per-keyframe floors) against a Monte Carlo of the simulator's
// encoders (sim_run.h defaults: 0.1 % radius errors, 1e-5 m^2/m random wheel
// travel, slips) over keyframe-length motions: the odometry factor between two
// keyframes must be neither overconfident nor far too cautious.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <vector>

#include "encoder_test_paths.h"
#include "groundline/localization/sliding_window_smoother.h"
#include "groundline/sim/sim_run.h"

namespace groundline::sim {
namespace {

using namespace testing;  // NOLINT: the shared test helpers

struct Consistency {
  Vector3 component_mean = Vector3::Zero();  // mean e_i^2 / Sigma_ii (1 expected)
  double nees_mean = 0.0;                    // mean e^T Sigma^-1 e (3 expected)
};

// Over `runs` seeds: the keyframe's odometry T_start_end and covariance
// (with the smoother's floors, as in its odometry factor) against the truth.
Consistency KeyframeConsistency(const core::Trajectory& truth,
                                const localization::OdometryNoiseParams& noise, int runs) {
  const DiffDriveParams drive;
  const localization::SmootherOptions smoother;
  const double floor_m2 = smoother.odometry_sigma_floor_m * smoother.odometry_sigma_floor_m;
  const double floor_rad2 = smoother.odometry_sigma_floor_rad * smoother.odometry_sigma_floor_rad;
  WheelEncoderOptions encoders = SimRunOptions().encoders;
  const SE2 T_start_end = truth.front().pose.Between(truth.back().pose);
  Consistency out;
  for (int run = 0; run < runs; ++run) {
    encoders.seed = 5000 + run;
    const core::Result<WheelEncoderLog> log = SimulateWheelEncoders(truth, drive, encoders);
    EXPECT_TRUE(log.ok()) << log.message();
    if (!log.ok()) return out;
    OdometryIntegrator odometry(drive, noise);
    for (const EncoderReading& r : log->readings) odometry.Integrate(r.increment);
    const localization::RelativeMotion motion = odometry.StartKeyframe();
    const core::Matrix3 covariance =
        motion.covariance + Vector3(floor_m2, floor_m2, floor_rad2).asDiagonal().toDenseMatrix();
    const Vector3 e = T_start_end.Minus(motion.T_start_end);  // truth = odometry * Exp(e)
    out.component_mean += e.cwiseAbs2().cwiseQuotient(covariance.diagonal()) / runs;
    out.nees_mean += e.dot(covariance.ldlt().solve(e)) / runs;
  }
  return out;
}

// One keyframe of the 1.2 km zone runs: 0.75 m at 1.5 m/s (encoders at
// 100 Hz), straight or turning 25 deg.
const std::vector<core::Trajectory>& KeyframeMotions() {
  static const std::vector<core::Trajectory> motions = {
      TruthFromSegments({{0.75, 0.0, 50}}), TruthFromSegments({{0.75, 25.0 * kPi / 180.0, 50}})};
  return motions;
}

// With the simulator's random wheel error (1e-5 m^2/m; its slips are left to
// the gate's slip hypothesis) and the consistent lateral variance (1e-7
// m^2/m: the simulator has no lateral error source).
TEST(KeyframeOdometryNoise, TheWheelVarianceIsConsistentWithTheSimulatedEncoders) {
  const OdometryNoiseParams noise =
      localization::OdometryNoiseFromWheelVariance(1e-5, DiffDriveParams().track_m, 1e-7);
  for (const core::Trajectory& truth : KeyframeMotions()) {
    const Consistency c = KeyframeConsistency(truth, noise, 1000);
    // Measured (straight; turning): x 1.10, 0.93; lateral 1.30, 1.06;
    // yaw 1.27, 1.06; NEES 3.22, 2.65 (the slips, in the Monte Carlo but not
    // in the model, lift the means a little; the turn's diagonal model
    // overestimates a turn's heading variance by q |dtheta| / B). With the
    // former 1.27e-5, 1e-6 and 1 mm floor: 0.64-1.00, NEES 2.09, 1.78.
    for (int i = 0; i < 3; ++i) {
      EXPECT_GT(c.component_mean(i), 0.7) << "component " << i;
      EXPECT_LT(c.component_mean(i), 1.5) << "component " << i;
    }
    EXPECT_GT(c.nees_mean, 2.2);
    EXPECT_LT(c.nees_mean, 3.8);
  }
}

TEST(KeyframeOdometryNoise, TheSlipAllowanceMakesTheLateralVarianceFarTooCautious) {
  // The default lateral variance of `groundline localize`, 1e-3 m^2/m (3 cm
  // per sqrt(m), kept as the gate's allowance for wheel slips): between
  // keyframes the lateral error is the heading error carried along (~2 mm),
  // so the lateral variance is ~100x too wide.
  const OdometryNoiseParams noise =
      localization::OdometryNoiseFromWheelVariance(1e-5, DiffDriveParams().track_m, 1e-3);
  const Consistency c = KeyframeConsistency(KeyframeMotions().front(), noise, 1000);
  EXPECT_LT(c.component_mean(1), 0.05);
}

}  // namespace
}  // namespace groundline::sim
