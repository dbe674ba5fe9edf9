// Differential-drive kinematics and increment noise: exact geometry of
// straight lines, turns in place and circles; the noise model and its
// derivation from per-wheel errors; parameter validation.
#include "groundline/localization/diff_drive_odometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "groundline/localization/odometry_integrator.h"
#include "jacobian_check.h"
#include "test_units.h"

namespace groundline::localization {
namespace {

using core::Matrix3;
using core::SE2;
using core::Vector3;
using ::groundline::testing::kPi;

TEST(DiffDriveOdometry, StraightLineIsExact) {
  const DiffDriveParams drive;  // r = 0.125 m, B = 0.760 m
  OdometryIntegrator odometry(drive, OdometryNoiseParams{});
  for (int i = 0; i < 10; ++i) odometry.Integrate(WheelAngleIncrement{1.0, 1.0});
  EXPECT_TRUE(odometry.T_odom_base().IsApprox(SE2(1.25, 0.0, 0.0), 1e-14, 0.0));
  for (int i = 0; i < 10; ++i) odometry.Integrate(WheelAngleIncrement{-0.5, -0.5});
  EXPECT_TRUE(odometry.T_odom_base().IsApprox(SE2(0.625, 0.0, 0.0), 1e-14, 0.0));
  EXPECT_NEAR(odometry.since_reset().path_length_m, 1.875, 1e-14);
}

TEST(DiffDriveOdometry, TurnInPlaceIsExact) {
  const DiffDriveParams drive;
  OdometryIntegrator odometry(drive, OdometryNoiseParams{});
  const OdometryIncrement inc = odometry.Integrate(WheelAngleIncrement{-1.0, 1.0});
  EXPECT_NEAR(inc.rotation_rad, 2.0 * 0.125 / 0.760, 1e-15);
  EXPECT_EQ(inc.distance_m, 0.0);
  for (int i = 1; i < 5; ++i) odometry.Integrate(WheelAngleIncrement{-1.0, 1.0});
  EXPECT_TRUE(odometry.T_odom_base().IsApprox(SE2(0.0, 0.0, 5.0 * 0.25 / 0.76), 1e-15, 1e-14));
}

TEST(DiffDriveOdometry, CircleOfKnownRadiusCloses) {
  // Radius 2 m, counter-clockwise: the centre is at (0, 2), half-way is (0, 4, pi).
  const DiffDriveParams drive;
  constexpr double kRadiusM = 2.0;
  constexpr int kSteps = 97;  // any step count: each step is an exact arc
  const double dtheta = 2.0 * kPi / kSteps;
  const WheelAngleIncrement wheels = WheelsFromArc(drive, kRadiusM * dtheta, dtheta);
  // Outer (right) wheel runs on radius R + B/2.
  EXPECT_NEAR(wheels.right_rad / wheels.left_rad, (kRadiusM + 0.38) / (kRadiusM - 0.38), 1e-12);
  OdometryIntegrator odometry(drive, OdometryNoiseParams{});
  for (int i = 0; i < kSteps; ++i) {
    odometry.Integrate(wheels);
    const SE2& T = odometry.T_odom_base();
    EXPECT_NEAR((T.translation() - core::Vector2(0.0, kRadiusM)).norm(), kRadiusM, 1e-12);
    EXPECT_NEAR(T.yaw(), core::WrapAngle((i + 1) * dtheta), 1e-12);
  }
  EXPECT_TRUE(odometry.T_odom_base().IsApprox(SE2(), 1e-12, 1e-12));
  EXPECT_NEAR(odometry.since_reset().path_length_m, 2.0 * kPi * kRadiusM, 1e-12);
}

// Calibrated per-wheel radii: each wheel's travel is its own radius times its
// angle; 0 falls back to the nominal radius; a negative radius is refused.
TEST(DiffDriveOdometry, EachWheelRollsItsOwnCalibratedRadius) {
  DiffDriveParams drive;
  drive.wheel_radius_m = 0.125;
  drive.track_m = 0.76;
  drive.left_wheel_radius_m = 0.126;
  drive.right_wheel_radius_m = 0.124;
  // Equal wheel angles: the left wheel rolls further, the vehicle turns right.
  const OdometryIncrement inc = IncrementFromWheels(drive, OdometryNoiseParams{}, {8.0, 8.0});
  EXPECT_NEAR(inc.distance_m, 0.5 * (0.126 + 0.124) * 8.0, 1e-12);
  EXPECT_NEAR(inc.rotation_rad, (0.124 - 0.126) * 8.0 / 0.76, 1e-12);
  // WheelsFromArc is its inverse with the same radii.
  const WheelAngleIncrement back = WheelsFromArc(drive, inc.distance_m, inc.rotation_rad);
  EXPECT_NEAR(back.left_rad, 8.0, 1e-12);
  EXPECT_NEAR(back.right_rad, 8.0, 1e-12);
  drive.right_wheel_radius_m = 0.0;  // unset: the nominal radius
  EXPECT_DOUBLE_EQ(drive.RightRadius(), 0.125);
  EXPECT_TRUE(drive.Validate().ok());
  drive.left_wheel_radius_m = -0.1;
  const core::Status bad = drive.Validate();
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("left_wheel_radius_m"), std::string::npos) << bad.message();
}

TEST(DiffDriveOdometry, WheelsFromArcInvertsTheKinematics) {
  const DiffDriveParams drive{0.1, 0.5};
  for (const auto& [ds, dtheta] : {std::pair{0.3, 0.0}, {0.0, -0.4}, {-0.2, 0.1}, {0.05, 2.0}}) {
    const OdometryIncrement inc =
        IncrementFromWheels(drive, OdometryNoiseParams{}, WheelsFromArc(drive, ds, dtheta));
    EXPECT_NEAR(inc.distance_m, ds, 1e-15);
    EXPECT_NEAR(inc.rotation_rad, dtheta, 1e-15);
    EXPECT_TRUE(inc.T_prev_curr.IsApprox(SE2::Exp(Vector3(ds, 0.0, dtheta)), 1e-15, 1e-15));
  }
}

TEST(DiffDriveOdometry, WheelsFromIncrementInvertsTheIncrementAndDropsTheLateralPart) {
  const DiffDriveParams drive{0.1, 0.5};
  for (const auto& [left, right] :
       {std::pair{0.3, 0.3}, {-0.4, 0.4}, {-0.2, -0.1}, {0.05, 2.0}, {3.0, -3.0}}) {
    const OdometryIncrement inc =
        IncrementFromWheels(drive, OdometryNoiseParams{}, WheelAngleIncrement{left, right});
    double lateral_m = 1.0;
    const WheelAngleIncrement back = WheelsFromIncrement(drive, inc.T_prev_curr, &lateral_m);
    EXPECT_NEAR(back.left_rad, left, 1e-12);
    EXPECT_NEAR(back.right_rad, right, 1e-12);
    EXPECT_NEAR(lateral_m, 0.0, 1e-15);
  }
  // A sideways component (a fused source's correction) is not wheel motion.
  const SE2 sideways = SE2::Exp(Vector3(0.2, 0.01, 0.1));
  double lateral_m = 0.0;
  const WheelAngleIncrement w = WheelsFromIncrement(drive, sideways, &lateral_m);
  EXPECT_NEAR(lateral_m, 0.01, 1e-15);
  const OdometryIncrement inc = IncrementFromWheels(drive, OdometryNoiseParams{}, w);
  EXPECT_NEAR(inc.distance_m, 0.2, 1e-12);
  EXPECT_NEAR(inc.rotation_rad, 0.1, 1e-12);
}

TEST(DiffDriveOdometry, KinematicsJacobianMatchesNumeric) {
  // d(ds, dtheta)/d(phi_L, phi_R) = [r/2, r/2; -r/B, r/B], the Jacobian that
  // maps per-wheel noise into OdometryNoiseFromWheelVariance.
  const DiffDriveParams drive;
  const double r = drive.wheel_radius_m, b = drive.track_m;
  Eigen::Matrix2d analytic;
  analytic << r / 2.0, r / 2.0, -r / b, r / b;
  const auto f = [&](const Eigen::Vector2d& phi) {
    const OdometryIncrement inc =
        IncrementFromWheels(drive, OdometryNoiseParams{}, WheelAngleIncrement{phi(0), phi(1)});
    return Eigen::Vector2d(inc.distance_m, inc.rotation_rad);
  };
  EXPECT_JACOBIAN_NEAR(analytic, f, Eigen::Vector2d(0.7, -0.3), 1e-9);
}

TEST(DiffDriveOdometry, IncrementCovarianceFollowsTheModel) {
  OdometryNoiseParams noise;
  noise.k_d = 1e-3;
  noise.k_lat = 2e-4;
  noise.k_theta = 3e-3;
  noise.k_theta_d = 4e-4;
  noise.k_d_theta = 5e-5;
  const Matrix3 cov = IncrementCovariance(noise, -0.5, 0.2);  // reversing, turning left
  Matrix3 expected = Matrix3::Zero();
  expected.diagonal() << 1e-3 * 0.5 + 5e-5 * 0.2, 2e-4 * 0.5, 3e-3 * 0.2 + 4e-4 * 0.5;
  EXPECT_TRUE(cov.isApprox(expected, 1e-15));
  EXPECT_EQ(IncrementCovariance(noise, 0.0, 0.0), Matrix3::Zero());
}

TEST(DiffDriveOdometry, NoiseFromWheelVarianceMatchesPerWheelPropagation) {
  // Per-wheel distance variance q |d_wheel| propagated through the kinematics
  // Jacobian must give the model covariance for straight driving and for
  // turning in place (where the model is exact).
  const DiffDriveParams drive;
  const double r = drive.wheel_radius_m, b = drive.track_m;
  constexpr double kQ = 3e-4;
  const OdometryNoiseParams noise = OdometryNoiseFromWheelVariance(kQ, b, 1e-6);
  ASSERT_TRUE(noise.Validate().ok()) << noise.Validate().message();
  Eigen::Matrix2d j;  // (ds, dtheta) from wheel *distances*
  j << 0.5, 0.5, -1.0 / b, 1.0 / b;
  for (const auto& [ds, dtheta] : {std::pair{0.4, 0.0}, {-0.4, 0.0}, {0.0, 0.9}, {0.0, -0.3}}) {
    const WheelAngleIncrement w = WheelsFromArc(drive, ds, dtheta);
    const Eigen::Matrix2d wheel_cov =
        Eigen::Vector2d(kQ * std::abs(r * w.left_rad), kQ * std::abs(r * w.right_rad)).asDiagonal();
    const Eigen::Matrix2d expected = j * wheel_cov * j.transpose();
    const Matrix3 model = IncrementCovariance(noise, ds, dtheta);
    EXPECT_NEAR(model(0, 0), expected(0, 0), 1e-15);
    EXPECT_NEAR(model(2, 2), expected(1, 1), 1e-15);
    EXPECT_NEAR(expected(0, 1), 0.0, 1e-15);  // uncorrelated in these two cases
  }
  // The documented defaults are this mapping for q = 2e-4, B = 0.760, k_lat = 1e-5.
  const OdometryNoiseParams defaults;
  const OdometryNoiseParams mapped = OdometryNoiseFromWheelVariance(2e-4, 0.760, 1e-5);
  EXPECT_NEAR(defaults.k_d, mapped.k_d, 0.02 * mapped.k_d);
  EXPECT_NEAR(defaults.k_theta, mapped.k_theta, 0.02 * mapped.k_theta);
  EXPECT_NEAR(defaults.k_theta_d, mapped.k_theta_d, 0.02 * mapped.k_theta_d);
  EXPECT_NEAR(defaults.k_d_theta, mapped.k_d_theta, 0.02 * mapped.k_d_theta);
  EXPECT_EQ(defaults.k_lat, mapped.k_lat);
}

TEST(DiffDriveParams, ValidateNamesTheBadField) {
  EXPECT_TRUE(DiffDriveParams{}.Validate().ok());
  DiffDriveParams bad;
  bad.wheel_radius_m = -0.1;
  EXPECT_EQ(bad.Validate().message(),
            "DiffDriveParams.wheel_radius_m: expected a finite value > 0 [m], got -0.1");
  bad = DiffDriveParams{};
  bad.track_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(bad.Validate().message(),
            "DiffDriveParams.track_m: expected a finite value > 0 [m], got nan");
  bad.track_m = 0.0;
  EXPECT_FALSE(bad.Validate().ok());
}

TEST(OdometryNoiseParams, ValidateNamesTheBadField) {
  EXPECT_TRUE(OdometryNoiseParams{}.Validate().ok());
  OdometryNoiseParams p;
  p.k_lat = 0.0;
  EXPECT_EQ(p.Validate().message(),
            "OdometryNoiseParams.k_lat: expected a finite value > 0 [m^2/m], got 0");
  p = OdometryNoiseParams{};
  p.k_theta = std::numeric_limits<double>::infinity();
  EXPECT_EQ(p.Validate().message(),
            "OdometryNoiseParams.k_theta: expected a finite value > 0 [rad^2/rad], got inf");
  p = OdometryNoiseParams{};
  p.k_theta_d = 0.0;  // cross terms may be zero
  p.k_d_theta = 0.0;
  EXPECT_TRUE(p.Validate().ok());
  p.k_theta_d = -1e-4;
  EXPECT_EQ(p.Validate().message(),
            "OdometryNoiseParams.k_theta_d: expected a finite value >= 0 [rad^2/m], got -0.0001");
  p = OdometryNoiseParams{};
  p.k_d = -1.0;
  EXPECT_NE(p.Validate().message().find("OdometryNoiseParams.k_d:"), std::string::npos);
}

}  // namespace
}  // namespace groundline::localization
