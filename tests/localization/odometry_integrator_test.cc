// OdometryIntegrator: covariance propagation against closed forms and Monte
// Carlo, the Compose Jacobians it relies on, keyframe spans and Reset.
#include "groundline/localization/odometry_integrator.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <random>
#include <vector>

#include "groundline/core/random_draws.h"
#include "jacobian_check.h"

namespace groundline::localization {
namespace {

using core::Matrix3;
using core::SE2;
using core::Vector3;

// A mixed drive: straight, left arc, turn in place, reversing right arc.
std::vector<WheelAngleIncrement> MixedDrive(const DiffDriveParams& drive) {
  std::vector<WheelAngleIncrement> steps;
  for (int i = 0; i < 40; ++i) steps.push_back(WheelsFromArc(drive, 0.10, 0.0));
  for (int i = 0; i < 30; ++i) steps.push_back(WheelsFromArc(drive, 0.10, 0.05));
  for (int i = 0; i < 20; ++i) steps.push_back(WheelsFromArc(drive, 0.0, -0.08));
  for (int i = 0; i < 30; ++i) steps.push_back(WheelsFromArc(drive, -0.05, -0.03));
  return steps;
}

TEST(OdometryIntegrator, StraightLineCovarianceHasClosedForm) {
  // Driving straight n steps of d: var(x) = k_d L, var(yaw) = k_theta_d L,
  // var(y) = k_lat L + k_theta_d d^3 sum_{i<n} i^2 (heading error integrated
  // into lateral error), cov(y, yaw) = k_theta_d d^2 n(n-1)/2.
  const DiffDriveParams drive;
  const OdometryNoiseParams noise;
  OdometryIntegrator odometry(drive, noise);
  constexpr int kSteps = 500;
  constexpr double kStepM = 0.02;
  for (int i = 0; i < kSteps; ++i) odometry.Integrate(WheelsFromArc(drive, kStepM, 0.0));
  const double length_m = kSteps * kStepM;
  const double n = kSteps;
  const Matrix3& cov = odometry.covariance();
  EXPECT_NEAR(cov(0, 0), noise.k_d * length_m, 1e-15);
  EXPECT_NEAR(cov(2, 2), noise.k_theta_d * length_m, 1e-15);
  const double sum_i2 = (n - 1.0) * n * (2.0 * n - 1.0) / 6.0;
  EXPECT_NEAR(cov(1, 1), noise.k_lat * length_m + noise.k_theta_d * std::pow(kStepM, 3) * sum_i2,
              1e-12);
  EXPECT_NEAR(cov(1, 2), noise.k_theta_d * kStepM * kStepM * n * (n - 1.0) / 2.0, 1e-12);
  EXPECT_NEAR(cov(0, 1), 0.0, 1e-15);
  EXPECT_NEAR(cov(0, 2), 0.0, 1e-15);
}

TEST(OdometryIntegrator, PropagationJacobiansMatchNumeric) {
  // The integrator uses d(T*D)/dT = Ad(D^-1) and d(T*D)/dD = I.
  const DiffDriveParams drive;
  const OdometryNoiseParams noise;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vector3 xi = Vector3(5.0, 5.0, 3.14159).cwiseProduct(core::DrawVector<3>(u, rng));
    const SE2 T(xi(0), xi(1), xi(2));
    const OdometryIncrement inc =
        IncrementFromWheels(drive, noise, WheelAngleIncrement{2.0 * u(rng), 2.0 * u(rng)});
    const SE2& D = inc.T_prev_curr;
    Matrix3 j_t, j_d;
    T.Compose(D, &j_t, &j_d);
    EXPECT_TRUE(j_t.isApprox(D.Inverse().Adjoint()));
    EXPECT_EQ(j_d, Matrix3::Identity());
    const auto f_t = [&](const SE2& v) { return v * D; };
    const auto f_d = [&](const SE2& v) { return T * v; };
    EXPECT_JACOBIAN_NEAR(j_t, f_t, T, 1e-7);
    EXPECT_JACOBIAN_NEAR(j_d, f_d, D, 1e-7);
  }
}

TEST(OdometryIntegrator, CovarianceMatchesMonteCarlo) {
  // Sample each increment as D * Exp(w), w ~ N(0, Sigma_D), integrate, and
  // compare the sample covariance of T_nominal^-1 T_sample (right
  // perturbation at the noise-free pose) with the propagated covariance.
  const DiffDriveParams drive;
  const OdometryNoiseParams noise;
  const std::vector<WheelAngleIncrement> steps = MixedDrive(drive);
  OdometryIntegrator odometry(drive, noise);
  std::vector<OdometryIncrement> increments;
  for (const WheelAngleIncrement& w : steps) increments.push_back(odometry.Integrate(w));
  const SE2 nominal = odometry.T_odom_base();
  const Matrix3 propagated = odometry.covariance();

  constexpr int kRuns = 10000;
  std::mt19937_64 rng(20240611);
  std::normal_distribution<double> normal;
  Matrix3 second_moment = Matrix3::Zero();
  Vector3 mean = Vector3::Zero();
  for (int run = 0; run < kRuns; ++run) {
    SE2 T;
    for (const OdometryIncrement& inc : increments) {
      const Vector3 sd = inc.covariance.diagonal().cwiseSqrt();
      const Vector3 w = sd.cwiseProduct(core::DrawVector<3>(normal, rng));
      T = T * inc.T_prev_curr * SE2::Exp(w);
    }
    const Vector3 e = T.Minus(nominal);
    second_moment += e * e.transpose() / kRuns;
    mean += e / kRuns;
  }
  // Generalized eigenvalues of (sample, propagated): all 1 for a perfect match.
  const Eigen::LLT<Matrix3> llt(propagated);
  const Matrix3 l_inv = llt.matrixL().solve(Matrix3::Identity());
  const Vector3 ratios =
      Eigen::SelfAdjointEigenSolver<Matrix3>(l_inv * second_moment * l_inv.transpose())
          .eigenvalues();
  EXPECT_GT(ratios.minCoeff(), 0.9) << ratios.transpose();
  EXPECT_LT(ratios.maxCoeff(), 1.1) << ratios.transpose();
  // First order predicts no bias; allow 10% of the standard deviation.
  const Vector3 sd = propagated.diagonal().cwiseSqrt();
  EXPECT_LT(mean.cwiseQuotient(sd).cwiseAbs().maxCoeff(), 0.1) << mean.transpose();
}

TEST(OdometryIntegrator, KeyframeSpansChainAndStartFromZeroCovariance) {
  const DiffDriveParams drive;
  const OdometryNoiseParams noise;
  const std::vector<WheelAngleIncrement> steps = MixedDrive(drive);
  OdometryIntegrator odometry(drive, noise);
  SE2 chained;
  std::vector<RelativeMotion> spans;
  for (size_t i = 0; i < steps.size(); ++i) {
    odometry.Integrate(steps[i]);
    if (i % 25 == 24 || i + 1 == steps.size()) spans.push_back(odometry.StartKeyframe());
  }
  EXPECT_EQ(odometry.SinceKeyframe().num_increments, 0);
  EXPECT_EQ(odometry.SinceKeyframe().covariance, Matrix3::Zero());
  int total = 0;
  for (const RelativeMotion& span : spans) {
    chained = chained * span.T_start_end;
    total += span.num_increments;
  }
  EXPECT_EQ(total, static_cast<int>(steps.size()));
  EXPECT_TRUE(chained.IsApprox(odometry.T_odom_base(), 1e-12, 1e-12));
  // The second span equals a fresh integration of its 25 readings.
  OdometryIntegrator fresh(drive, noise);
  for (size_t i = 25; i < 50; ++i) fresh.Integrate(steps[i]);
  EXPECT_TRUE(fresh.T_odom_base().IsApprox(spans[1].T_start_end, 1e-14, 1e-14));
  EXPECT_TRUE(fresh.covariance().isApprox(spans[1].covariance, 1e-12));
}

TEST(OdometryIntegrator, ResetCarriesInitialCovarianceThroughMotion) {
  const DiffDriveParams drive;
  const OdometryNoiseParams noise;
  OdometryIntegrator odometry(drive, noise);
  odometry.Integrate(WheelsFromArc(drive, 1.0, 0.3));
  Matrix3 initial = Matrix3::Zero();
  initial(2, 2) = 1e-2;  // only yaw uncertain at the start
  const SE2 start(3.0, -1.0, 0.5);
  odometry.Reset(start, initial);
  EXPECT_EQ(odometry.since_reset().num_increments, 0);
  EXPECT_EQ(odometry.SinceKeyframe().num_increments, 0);
  odometry.Integrate(WheelsFromArc(drive, 2.0, 0.0));
  EXPECT_TRUE(odometry.T_odom_base().IsApprox(start * SE2(2.0, 0.0, 0.0), 1e-14, 1e-14));
  // A yaw error at the start becomes a lateral error of 2 m * yaw error.
  EXPECT_NEAR(odometry.covariance()(1, 1), 4.0 * 1e-2 + noise.k_lat * 2.0, 1e-12);
  EXPECT_NEAR(odometry.covariance()(1, 2), 2.0 * 1e-2, 1e-12);
  // The keyframe span does not include the initial covariance.
  EXPECT_NEAR(odometry.SinceKeyframe().covariance(1, 1), noise.k_lat * 2.0, 1e-15);
}

}  // namespace
}  // namespace groundline::localization
