#include "groundline/core/trajectory_metrics.h"
#include "test_units.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>
#include <random>

#include "groundline/core/random_draws.h"

namespace groundline::core {
namespace {

using ::groundline::testing::kDeg;
using ::groundline::testing::kPi;

// 10 Hz poses along a gentle S-curve.
Trajectory Curve(std::size_t n) {
  Trajectory trajectory;
  SE2 pose(1.0, -0.5, 0.2);
  for (std::size_t i = 0; i < n; ++i) {
    trajectory.push_back({0.1 * static_cast<double>(i), pose, std::nullopt});
    pose = pose * SE2::Exp(Vector3(0.1, 0.0, 0.03 * std::sin(0.05 * static_cast<double>(i))));
  }
  return trajectory;
}

// Straight along +x at 1 m/s, 10 Hz, heading 0.
Trajectory StraightX(std::size_t n) {
  Trajectory trajectory;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 0.1 * static_cast<double>(i);
    trajectory.push_back({t, SE2(t, 0.0, 0.0), std::nullopt});
  }
  return trajectory;
}

TEST(ErrorStats, HandComputed) {
  const ErrorStats even = ComputeErrorStats({4.0, 1.0, 3.0, 2.0});
  EXPECT_EQ(even.n, 4u);
  EXPECT_DOUBLE_EQ(even.mean, 2.5);
  EXPECT_DOUBLE_EQ(even.median, 2.5);
  EXPECT_DOUBLE_EQ(even.max, 4.0);
  EXPECT_DOUBLE_EQ(even.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(even.std_dev, std::sqrt(1.25));  // population, not sample (sqrt(5/3))
  const ErrorStats odd = ComputeErrorStats({5.0, 1.0, 3.0});
  EXPECT_DOUBLE_EQ(odd.median, 3.0);
  EXPECT_EQ(ComputeErrorStats({}).n, 0u);
}

TEST(TrajectoryMetrics, AlongAndCrossTrackOfAConstantOffset) {
  const Trajectory reference = StraightX(50);
  Trajectory estimate = reference;
  for (StampedPose& p : estimate) p.pose = SE2(p.pose.x() + 0.1, p.pose.y() + 0.05, 0.0);
  const Result<TrajectoryErrorSummary> s = ComputeTrajectoryErrors(estimate, reference);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->n_matched, 50u);
  EXPECT_EQ(s->n_unmatched, 0u);
  EXPECT_NEAR(s->along_rmse_m, 0.1, 1e-12);
  EXPECT_NEAR(s->cross_rmse_m, 0.05, 1e-12);
  EXPECT_NEAR(s->ate_m.rmse, std::sqrt(0.0125), 1e-12);
  EXPECT_NEAR(s->ate_m.mean, std::sqrt(0.0125), 1e-12);
  EXPECT_NEAR(s->ate_m.median, std::sqrt(0.0125), 1e-12);
  EXPECT_NEAR(s->ate_m.max, std::sqrt(0.0125), 1e-12);
  EXPECT_NEAR(s->heading_rmse_deg, 0.0, 1e-12);
  EXPECT_FALSE(s->T_ref_est.has_value());
  EXPECT_FALSE(s->nees.has_value());
  EXPECT_EQ(s->n_direction_from_heading, 0u);
}

TEST(TrajectoryMetrics, AlongAndCrossSignsFollowTheDirectionOfTravel) {
  // Reference driving along +y; the estimate 0.1 m ahead (+y) and 0.05 m to the left (-x).
  PosePair pair;
  pair.T_map_ref = SE2(2.0, 3.0, kPi / 2);
  pair.T_map_est = SE2(1.95, 3.1, kPi / 2 + 0.1);
  pair.ref_direction_map = Vector2(0.0, 1.0);
  const std::vector<PoseError> e = ComputePoseErrors({pair});
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NEAR(e[0].along_m, 0.1, 1e-12);
  EXPECT_NEAR(e[0].cross_m, 0.05, 1e-12);
  EXPECT_NEAR(e[0].heading_error_rad, 0.1, 1e-12);
}

TEST(TrajectoryMetrics, HeadingErrorWrapsAcrossPi) {
  Trajectory reference = StraightX(20);
  Trajectory estimate = reference;
  for (StampedPose& p : reference) p.pose = SE2(p.pose.translation(), 179.0 * kDeg);
  for (StampedPose& p : estimate) p.pose = SE2(p.pose.translation(), -179.0 * kDeg);
  const Result<TrajectoryErrorSummary> s = ComputeTrajectoryErrors(estimate, reference);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_NEAR(s->heading_rmse_deg, 2.0, 1e-9);
  EXPECT_NEAR(s->ate_m.max, 0.0, 1e-12);
}

TEST(TrajectoryMetrics, AlignmentRecoversARigidMotion) {
  const Trajectory reference = Curve(300);
  const SE2 T_est_ref(3.0, -2.0, 0.7);  // the estimate lives in a moved map frame
  Trajectory estimate = reference;
  for (StampedPose& p : estimate) p.pose = T_est_ref * p.pose;

  const Result<TrajectoryErrorSummary> raw = ComputeTrajectoryErrors(estimate, reference);
  ASSERT_TRUE(raw.ok()) << raw.message();
  EXPECT_GT(raw->ate_m.rmse, 1.0);
  EXPECT_NEAR(raw->heading_rmse_deg, 0.7 / kDeg, 1e-9);

  TrajectoryMetricsOptions options;
  options.align = true;
  const Result<TrajectoryErrorSummary> aligned =
      ComputeTrajectoryErrors(estimate, reference, options);
  ASSERT_TRUE(aligned.ok()) << aligned.message();
  EXPECT_LT(aligned->ate_m.max, 1e-9);
  EXPECT_LT(aligned->heading_rmse_deg, 1e-9);
  ASSERT_TRUE(aligned->T_ref_est.has_value());
  EXPECT_TRUE(aligned->T_ref_est->IsApprox(T_est_ref.Inverse(), 1e-9, 1e-12));
}

TEST(TrajectoryMetrics, AlignmentIsTheLeastSquaresFitUnderNoise) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<Vector2> est, ref;
  const SE2 T_ref_est(-1.0, 0.5, -2.0);
  for (int i = 0; i < 400; ++i) {
    const Vector2 p(0.05 * i, 2.0 * std::sin(0.02 * i));
    est.push_back(p);
    ref.push_back(T_ref_est * p + DrawVector<2>(noise, rng));
  }
  const Result<SE2> fit = AlignSE2(est, ref);
  ASSERT_TRUE(fit.ok()) << fit.message();
  EXPECT_TRUE(fit->IsApprox(T_ref_est, 0.01, 0.002));
  // Optimality: a small perturbation of the fit never lowers the cost.
  auto cost = [&](const SE2& T) {
    double c = 0.0;
    for (std::size_t i = 0; i < est.size(); ++i) c += (ref[i] - T * est[i]).squaredNorm();
    return c;
  };
  for (int k = 0; k < 3; ++k) {
    for (double h : {-1e-4, 1e-4}) {
      Vector3 d = Vector3::Zero();
      d(k) = h;
      EXPECT_GE(cost(*fit * SE2::Exp(d)), cost(*fit));
    }
  }
}

TEST(TrajectoryMetrics, DegenerateAlignmentIsAnError) {
  EXPECT_FALSE(AlignSE2({Vector2(1, 1)}, {Vector2(0, 0)}).ok());
  EXPECT_FALSE(AlignSE2({Vector2(1, 1), Vector2(1, 1)}, {Vector2(0, 0), Vector2(3, 0)}).ok());
  EXPECT_FALSE(AlignSE2({Vector2(1, 1)}, {Vector2(0, 0), Vector2(1, 0)}).ok());
  Trajectory still;
  for (int i = 0; i < 10; ++i) still.push_back({0.1 * i, SE2(1.0, 2.0, 0.3), std::nullopt});
  TrajectoryMetricsOptions options;
  options.align = true;
  const Result<TrajectoryErrorSummary> s = ComputeTrajectoryErrors(still, still, options);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("stationary"), std::string::npos) << s.message();
}

TEST(TrajectoryMetrics, InterpolationRemovesTheTimeOffsetErrorOfNearest) {
  // The estimate is exact but stamped 5 ms after each 10 Hz reference pose at 1 m/s.
  const Trajectory reference = StraightX(40);
  Trajectory estimate;
  for (std::size_t i = 0; i + 1 < reference.size(); ++i) {
    const double t = reference[i].stamp_s + 0.005;
    estimate.push_back({t, SE2(t, 0.0, 0.0), std::nullopt});
  }
  const Result<TrajectoryErrorSummary> nearest = ComputeTrajectoryErrors(estimate, reference);
  ASSERT_TRUE(nearest.ok());
  EXPECT_NEAR(nearest->ate_m.rmse, 0.005, 1e-9);
  EXPECT_NEAR(nearest->along_rmse_m, 0.005, 1e-9);
  EXPECT_NEAR(nearest->cross_rmse_m, 0.0, 1e-12);
  TrajectoryMetricsOptions options;
  options.association.method = AssociationMethod::kInterpolate;
  const Result<TrajectoryErrorSummary> interp =
      ComputeTrajectoryErrors(estimate, reference, options);
  ASSERT_TRUE(interp.ok());
  EXPECT_NEAR(interp->ate_m.rmse, 0.0, 1e-9);
  EXPECT_EQ(interp->association_method, AssociationMethod::kInterpolate);
}

TEST(TrajectoryMetrics, NeesOfSamplesFromTheReportedCovarianceIsChiSquare3) {
  Matrix3 covariance;
  covariance << 0.04, 0.01, 0.002, 0.01, 0.09, -0.003, 0.002, -0.003, 0.0025;
  const Matrix3 L = covariance.llt().matrixL();
  std::mt19937 rng(42);
  std::normal_distribution<double> normal;
  const Trajectory reference = Curve(4000);
  Trajectory estimate = reference;
  for (StampedPose& p : estimate) {
    // e = Log(T_est^-1 T_ref) ~ N(0, Sigma)  <=>  T_est = T_ref Exp(e)^-1.
    const Vector3 e = L * DrawVector<3>(normal, rng);
    p.pose = p.pose * SE2::Exp(e).Inverse();
    p.covariance = covariance;
  }
  const Result<TrajectoryErrorSummary> s = ComputeTrajectoryErrors(estimate, reference);
  ASSERT_TRUE(s.ok()) << s.message();
  ASSERT_TRUE(s->nees.has_value());
  EXPECT_EQ(s->nees->n, 4000u);
  EXPECT_EQ(s->nees->n_invalid_covariance, 0u);
  EXPECT_NEAR(s->nees->in_band_share, 0.95, 0.015);  // 3 sigma of a binomial share
  EXPECT_NEAR(s->nees->mean, 3.0, 0.15);

  // An estimator claiming 10x smaller variances is caught.
  for (StampedPose& p : estimate) p.covariance = covariance / 10.0;
  const Result<TrajectoryErrorSummary> overconfident = ComputeTrajectoryErrors(estimate, reference);
  ASSERT_TRUE(overconfident.ok());
  EXPECT_LT(overconfident->nees->in_band_share, 0.5);
  EXPECT_GT(overconfident->nees->mean, 20.0);
}

TEST(TrajectoryMetrics, NeesErrorLivesInTheEstimateBodyFrame) {
  // Heading +90 deg; the estimate is 0.1 m behind along its own x axis, where
  // its covariance says 0.1 m (1 sigma): NEES 1. A map-frame error would be
  // along map y, where the covariance is 10x wider (NEES 0.01).
  PosePair pair;
  pair.T_map_ref = SE2(5.0, 5.0, kPi / 2);
  pair.T_map_est = pair.T_map_ref * SE2(-0.1, 0.0, 0.0);
  pair.est_covariance = Vector3(0.01, 1.0, 0.01).asDiagonal();
  const std::vector<PoseError> e = ComputePoseErrors({pair});
  ASSERT_TRUE(e[0].nees.has_value());
  EXPECT_NEAR(*e[0].nees, 1.0, 1e-12);
}

TEST(TrajectoryMetrics, NonPositiveDefiniteCovariancesAreCountedNotUsed) {
  Trajectory reference = StraightX(10);
  Trajectory estimate = reference;
  estimate[0].covariance = Matrix3::Identity();
  estimate[1].covariance = Matrix3::Zero();
  estimate[2].covariance = Vector3(1.0, -1.0, 1.0).asDiagonal();
  const Result<TrajectoryErrorSummary> s = ComputeTrajectoryErrors(estimate, reference);
  ASSERT_TRUE(s.ok());
  ASSERT_TRUE(s->nees.has_value());
  EXPECT_EQ(s->nees->n, 1u);
  EXPECT_EQ(s->nees->n_invalid_covariance, 2u);
  EXPECT_DOUBLE_EQ(s->nees->mean, 0.0);
  EXPECT_DOUBLE_EQ(s->nees->in_band_share, 0.0);  // exactly zero error is below the band
}

TEST(TrajectoryMetrics, RpeMeasuresScaleDriftPerDistance) {
  // The estimate travels 1 % too far: 1.01 m per reference metre.
  const Trajectory reference = StraightX(201);  // 20 m
  Trajectory estimate = reference;
  for (StampedPose& p : estimate) p.pose = SE2(1.01 * p.pose.x(), 0.0, 0.0);
  TrajectoryMetricsOptions options;
  // 9.95 m: the partner of pose i is pose i + 100 (10 m; 9.9 m is too short).
  options.rpe = RpeOptions{RpeDeltaUnit::kMetres, 9.95};
  const Result<TrajectoryErrorSummary> s = ComputeTrajectoryErrors(estimate, reference, options);
  ASSERT_TRUE(s.ok()) << s.message();
  ASSERT_TRUE(s->rpe.has_value());
  EXPECT_EQ(s->rpe->trans_m.n, 101u);
  EXPECT_NEAR(s->rpe->trans_m.rmse, 0.1, 1e-9);
  EXPECT_NEAR(s->rpe->trans_m.max, 0.1, 1e-9);
  EXPECT_NEAR(s->rpe->rot_deg.max, 0.0, 1e-9);
  options.rpe = RpeOptions{RpeDeltaUnit::kFrames, 1.0};
  const Result<TrajectoryErrorSummary> step = ComputeTrajectoryErrors(estimate, reference, options);
  ASSERT_TRUE(step.ok());
  EXPECT_EQ(step->rpe->trans_m.n, 200u);
  EXPECT_NEAR(step->rpe->trans_m.rmse, 0.001, 1e-9);
}

TEST(TrajectoryMetrics, RpeMeasuresYawDriftAndIgnoresAGlobalTransform) {
  const Trajectory reference = StraightX(100);
  Trajectory estimate = reference;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    estimate[i].pose = SE2(3.0, 1.0, 0.5) * SE2(estimate[i].pose.translation(), 0.001 * i);
  }
  const Result<RpeSummary> rpe =
      ComputeRpe(AssociateByStamp(estimate, reference)->pairs, {RpeDeltaUnit::kFrames, 5.0});
  ASSERT_TRUE(rpe.ok()) << rpe.message();
  EXPECT_EQ(rpe->rot_deg.n, 95u);
  EXPECT_NEAR(rpe->rot_deg.mean, 0.005 / kDeg, 1e-9);
  EXPECT_NEAR(rpe->rot_deg.max, 0.005 / kDeg, 1e-9);
  // Longer than the whole path: an error, not an empty result.
  const Result<RpeSummary> too_long =
      ComputeRpe(AssociateByStamp(estimate, reference)->pairs, {RpeDeltaUnit::kMetres, 50.0});
  EXPECT_FALSE(too_long.ok());
  EXPECT_FALSE((RpeOptions{RpeDeltaUnit::kFrames, 1.5}).Validate().ok());
  EXPECT_FALSE((RpeOptions{RpeDeltaUnit::kMetres, 0.0}).Validate().ok());
}

}  // namespace
}  // namespace groundline::core
