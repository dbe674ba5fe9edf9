// Floor extrinsics from tag corners: the analytic Jacobian, accuracy and the
// honesty of the 3-sigma bounds on seeded trials with 0.3 px corner noise,
// the base_link (single pose) layout, and the BEV error propagation.
#include "groundline/calibration/floor_extrinsics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "commissioning_fixture.h"
#include "groundline/core/random_draws.h"
#include "groundline/sim/commissioning_scene.h"
#include "jacobian_check.h"
#include "test_units.h"

namespace groundline::calibration {
namespace {

using ::groundline::testing::CommissioningSceneOrFail;
using ::groundline::testing::kDeg;
using Vector6d = Eigen::Matrix<double, 6, 1>;

Vector6d ToVector(const CameraMount& m) {
  Vector6d v;
  v << m.height_m, m.pitch_rad, m.roll_rad, m.yaw_rad, m.forward_m, m.lateral_m;
  return v;
}
CameraMount FromVector(const Vector6d& v) {
  CameraMount m;
  m.height_m = v(0);
  m.pitch_rad = v(1);
  m.roll_rad = v(2);
  m.yaw_rad = v(3);
  m.forward_m = v(4);
  m.lateral_m = v(5);
  return m;
}

// The corners of the scene's tags that fall inside the image, projected from
// the true mount, with Gaussian noise of sigma_px per axis.
std::vector<FloorImage> NoisyCorners(const sim::CommissioningScene& scene, double sigma_px,
                                     std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, sigma_px);
  std::vector<FloorImage> images;
  for (const VehiclePose& pose : scene.layout.vehicle_poses) {
    FloorImage im{pose.image, pose.T_floor_base, {}};
    for (const SurveyedTag& tag : scene.layout.tags) {
      const auto corners = tag.CornersInFrame();
      std::vector<FloorCorner> seen;
      for (int c = 0; c < 4; ++c) {
        const core::Result<Eigen::Vector2d> px =
            PredictFloorPixel(scene.camera, scene.true_mount, pose.T_floor_base, corners[c]);
        if (!px.ok() || !scene.camera.InImage(*px)) break;
        seen.push_back({tag.id, c, corners[c], *px + core::DrawVector<2>(noise, rng)});
      }
      if (seen.size() == 4) im.corners.insert(im.corners.end(), seen.begin(), seen.end());
    }
    images.push_back(std::move(im));
  }
  return images;
}

TEST(FloorExtrinsics, PixelJacobianMatchesNumericDifferentiation) {
  const sim::CommissioningScene scene =
      CommissioningSceneOrFail(sim::CommissioningOptions::Small());
  const core::SE2 T_floor_base(0.3, -0.05, 0.2);
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(1.2, 0.1), Eigen::Vector2d(1.0, -0.4), Eigen::Vector2d(1.5, 0.35)}) {
    MountJacobian J;
    ASSERT_TRUE(PredictFloorPixel(scene.camera, scene.true_mount, T_floor_base, p, &J).ok());
    const auto f = [&](const Vector6d& v) -> Eigen::Vector2d {
      return PredictFloorPixel(scene.camera, FromVector(v), T_floor_base, p).value();
    };
    EXPECT_JACOBIAN_NEAR(J, f, ToVector(scene.true_mount), 1e-4);
  }
}

TEST(FloorExtrinsics, RecoversTheMountAndItsBoundsHoldOnSeededTrials) {
  // 20 trials in CI; benchmarks/calibration/floor_extrinsics_trials runs 100.
  const sim::CommissioningScene scene = CommissioningSceneOrFail(sim::CommissioningOptions());
  const Vector6d truth = ToVector(scene.true_mount);
  constexpr int kTrials = 20;
  std::array<int, 6> inside{};
  Vector6d max_err = Vector6d::Zero();
  for (int trial = 0; trial < kTrials; ++trial) {
    std::mt19937_64 rng(1000 + trial);
    const std::vector<FloorImage> images = NoisyCorners(scene, 0.3, rng);
    core::Result<FloorExtrinsicsResult> r = SolveFloorExtrinsics(scene.camera, images, {});
    ASSERT_TRUE(r.ok()) << r.message();
    const Vector6d err = ToVector(r->mount) - truth;
    for (int i = 0; i < 6; ++i) {
      max_err(i) = std::max(max_err(i), std::abs(err(i)));
      if (std::abs(err(i)) <= 3.0 * std::sqrt(r->covariance(i, i))) ++inside[i];
    }
    EXPECT_NEAR(r->sigma_px, 0.3, 0.05);
  }
  std::printf(
      "max |error|: height %.3f mm pitch %.4f deg roll %.4f deg yaw %.4f deg "
      "forward %.3f mm lateral %.3f mm\n",
      1e3 * max_err(0), max_err(1) / kDeg, max_err(2) / kDeg, max_err(3) / kDeg, 1e3 * max_err(4),
      1e3 * max_err(5));
  EXPECT_LE(max_err(0), 0.5e-3);
  EXPECT_LE(max_err(1), 0.02 * kDeg);
  EXPECT_LE(max_err(2), 0.02 * kDeg);
  EXPECT_LE(max_err(3), 0.05 * kDeg);
  for (int i = 0; i < 6; ++i) EXPECT_GE(inside[i], kTrials - 1) << "parameter " << i;
}

TEST(FloorExtrinsics, SolvesFromOneStationaryViewWithTagsInBaseLink) {
  sim::CommissioningOptions options = sim::CommissioningOptions();
  options.poses = 1;
  options.start_x_m = 0.0;
  options.lateral_jitter_m = options.yaw_jitter_rad = 0.0;
  const sim::CommissioningScene scene = CommissioningSceneOrFail(options);
  std::mt19937_64 rng(7);
  std::vector<FloorImage> images = NoisyCorners(scene, 0.3, rng);
  ASSERT_EQ(images.size(), 1u);
  images[0].T_floor_base = core::SE2::Identity();  // base_link layout: identity pose
  ASSERT_GE(images[0].corners.size(), 16u);
  core::Result<FloorExtrinsicsResult> r = SolveFloorExtrinsics(scene.camera, images, {});
  ASSERT_TRUE(r.ok()) << r.message();
  const Vector6d err = ToVector(r->mount) - ToVector(scene.true_mount);
  for (int i = 0; i < 6; ++i) EXPECT_LE(std::abs(err(i)), 4.0 * std::sqrt(r->covariance(i, i)));
  EXPECT_LT(std::abs(err(0)), 2e-3);
}

TEST(FloorExtrinsics, NoiseFreeCornersGiveTheExactMount) {
  const sim::CommissioningScene scene =
      CommissioningSceneOrFail(sim::CommissioningOptions::Small());
  std::mt19937_64 rng(1);
  const std::vector<FloorImage> images = NoisyCorners(scene, 0.0, rng);
  core::Result<FloorExtrinsicsResult> r = SolveFloorExtrinsics(scene.camera, images, {});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_LT((ToVector(r->mount) - ToVector(scene.true_mount)).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT(r->rms_px, 1e-6);
  // The initialization alone is close (pooled homography on exact rays).
  EXPECT_LT((ToVector(r->initial_mount) - ToVector(scene.true_mount)).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(FloorExtrinsics, FailsWithTooFewCorners) {
  const sim::CommissioningScene scene =
      CommissioningSceneOrFail(sim::CommissioningOptions::Small());
  std::vector<FloorImage> images(1);
  images[0].corners.resize(4);
  core::Result<FloorExtrinsicsResult> r = SolveFloorExtrinsics(scene.camera, images, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("need at least 8"), std::string::npos) << r.message();
  FloorExtrinsicsOptions bad;
  bad.huber_px = 0.0;
  EXPECT_FALSE(SolveFloorExtrinsics(scene.camera, images, bad).ok());
}

TEST(FloorExtrinsics, BevErrorPropagatesTheMountCovariance) {
  const CameraMount mount;
  // A pure forward-offset uncertainty of 1 mm moves every BEV point 1 mm along x.
  Matrix6d cov = Matrix6d::Zero();
  cov(4, 4) = 1e-6;
  core::Result<BevError> e = BevErrorAhead(mount, cov, 2.0);
  ASSERT_TRUE(e.ok()) << e.message();
  EXPECT_NEAR(e->rms_mm, 1.0, 1e-9);
  EXPECT_NEAR(e->cov_floor_m2(0, 0), 1e-6, 1e-15);
  // A height uncertainty scales the floor distance from the camera: the point
  // d ahead of the camera moves by d / h per metre of height.
  cov.setZero();
  cov(0, 0) = 1e-6;
  e = BevErrorAhead(mount, cov, 2.0);
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(e->rms_mm, (2.0 - mount.forward_m) / mount.height_m, 1e-6);
  // A pitch uncertainty grows with distance (the ray grazes the floor).
  cov.setZero();
  cov(1, 1) = std::pow(0.01 * kDeg, 2);
  const double at1 = BevErrorAhead(mount, cov, 1.0)->rms_mm;
  const double at4 = BevErrorAhead(mount, cov, 4.0)->rms_mm;
  EXPECT_GT(at4, 4.0 * at1);
  // Behind the camera: no BEV.
  EXPECT_FALSE(BevErrorAhead(mount, cov, -1.0).ok());
}

}  // namespace
}  // namespace groundline::calibration
