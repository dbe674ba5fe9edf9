#include "groundline/calibration/camera_extrinsics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "groundline/core/random_draws.h"
#include "groundline/core/se2.h"
#include "jacobian_check.h"
#include "test_units.h"

namespace groundline::calibration {
namespace {

using ::groundline::testing::kDeg;
using ::groundline::testing::kPi;

// The reference camera: 6 mm lens, 5.3 um pixels, 1280 x 1024 sensor.
Eigen::Matrix3d ReferenceK() {
  const double f_px = 6.0e-3 / 5.3e-6;
  Eigen::Matrix3d K;
  K << f_px, 0.0, 640.0, 0.0, f_px, 512.0, 0.0, 0.0, 1.0;
  return K;
}

CameraMount ReferenceMount() {
  CameraMount mount;
  mount.height_m = 0.58;
  mount.pitch_rad = 42.4 * kDeg;
  mount.forward_m = 0.42;
  return mount;
}

CameraMount RandomMount(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  CameraMount mount;
  mount.height_m = 1.5 + 1.4 * unit(rng);
  mount.pitch_rad = 1.5 * unit(rng);
  mount.roll_rad = kPi * unit(rng);
  mount.yaw_rad = kPi * unit(rng);
  mount.forward_m = unit(rng);
  mount.lateral_m = unit(rng);
  return mount;
}

TEST(CameraMount, LevelCameraLooksAlongBaseX) {
  CameraMount mount = ReferenceMount();
  mount.pitch_rad = 0.0;
  const Eigen::Isometry3d T_base_cam = BaseFromCamera(mount);
  const Eigen::Matrix3d& r = T_base_cam.linear();
  EXPECT_TRUE(r.col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-15));   // optical axis
  EXPECT_TRUE(r.col(0).isApprox(-Eigen::Vector3d::UnitY(), 1e-15));  // image right
  EXPECT_TRUE(r.col(1).isApprox(-Eigen::Vector3d::UnitZ(), 1e-15));  // image down
  EXPECT_TRUE(T_base_cam.translation().isApprox(Eigen::Vector3d(0.42, 0.0, 0.58), 1e-15));
}

TEST(CameraMount, AnglesHaveTheDocumentedSenses) {
  CameraMount mount = ReferenceMount();
  mount.pitch_rad = 0.3;
  mount.roll_rad = 0.2;
  mount.yaw_rad = 0.4;
  const Eigen::Matrix3d r = BaseFromCamera(mount).linear();
  // Yaw and pitch alone place the optical axis; roll turns about it.
  const Eigen::Vector3d axis(std::cos(0.3) * std::cos(0.4), std::cos(0.3) * std::sin(0.4),
                             -std::sin(0.3));
  EXPECT_TRUE(r.col(2).isApprox(axis, 1e-14));
  EXPECT_GT(r.col(2).y(), 0.0);  // positive yaw looks left
  EXPECT_LT(r.col(2).z(), 0.0);  // positive pitch looks down
  // Positive roll lowers the image's right edge (camera x) below the horizontal.
  EXPECT_NEAR(r.col(0).z(), -std::sin(0.2) * std::cos(0.3), 1e-14);
}

TEST(CameraMount, ValidateNamesTheBadField) {
  CameraMount mount = ReferenceMount();
  EXPECT_TRUE(mount.Validate().ok());
  mount.height_m = 0.0;
  EXPECT_NE(mount.Validate().message().find("height_m"), std::string::npos);
  mount = ReferenceMount();
  mount.pitch_rad = kPi / 2;
  EXPECT_NE(mount.Validate().message().find("pitch_rad"), std::string::npos);
  mount = ReferenceMount();
  mount.forward_m = std::nan("");
  EXPECT_NE(mount.Validate().message().find("forward_m"), std::string::npos);
  mount = ReferenceMount();
  mount.yaw_rad = 3.2;
  EXPECT_NE(mount.Validate().message().find("yaw_rad"), std::string::npos);
  mount = ReferenceMount();
  mount.roll_rad = -3.2;
  EXPECT_NE(mount.Validate().message().find("roll_rad"), std::string::npos);
}

TEST(CameraMount, RoundTripThroughTransformOverRandomMounts) {
  std::mt19937 rng(20240611);
  for (int trial = 0; trial < 2000; ++trial) {
    const CameraMount mount = RandomMount(rng);
    ASSERT_TRUE(mount.Validate().ok());
    const core::Result<CameraMount> back = MountFromBaseCamera(BaseFromCamera(mount));
    ASSERT_TRUE(back.ok()) << back.message();
    EXPECT_NEAR(back->height_m, mount.height_m, 1e-12);
    EXPECT_NEAR(back->forward_m, mount.forward_m, 1e-12);
    EXPECT_NEAR(back->lateral_m, mount.lateral_m, 1e-12);
    EXPECT_NEAR(back->pitch_rad, mount.pitch_rad, 1e-9);
    EXPECT_NEAR(core::WrapAngle(back->roll_rad - mount.roll_rad), 0.0, 1e-9);
    EXPECT_NEAR(core::WrapAngle(back->yaw_rad - mount.yaw_rad), 0.0, 1e-9);
    EXPECT_TRUE(back->Validate().ok());
  }
}

TEST(CameraMount, InverseRejectsTransformsThatAreNotMounts) {
  Eigen::Isometry3d T = BaseFromCamera(ReferenceMount());
  Eigen::Isometry3d below = T;
  below.translation().z() = -0.1;
  EXPECT_NE(MountFromBaseCamera(below).message().find("not above the floor"), std::string::npos);

  Eigen::Isometry3d sheared = T;
  sheared.linear()(0, 1) += 1e-3;
  EXPECT_NE(MountFromBaseCamera(sheared).message().find("orthonormal"), std::string::npos);

  Eigen::Isometry3d down = T;  // optical axis straight down: pitch 90 deg
  CameraMount level = ReferenceMount();
  level.pitch_rad = 0.0;
  down.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                  BaseFromCamera(level).linear();
  EXPECT_NE(MountFromBaseCamera(down).message().find("vertical"), std::string::npos);
}

TEST(FloorHomography, MatchesRigidTransformAndPinholeProjection) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Matrix3d K = ReferenceK();
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const CameraMount mount = RandomMount(rng);
    const Eigen::Isometry3d T_base_cam = BaseFromCamera(mount);
    const Eigen::Matrix3d H = FloorToImageHomography(T_base_cam, K);
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector2d floor = 3.0 * core::DrawVector<2>(unit, rng);
      const Eigen::Vector3d p_cam = T_base_cam.inverse() * Eigen::Vector3d(floor.x(), floor.y(), 0);
      const core::Result<Eigen::Vector2d> pixel = ProjectFloorPoint(H, floor);
      if (p_cam.z() < 1e-3) {  // behind (or grazing) the camera
        if (p_cam.z() <= 0.0) {
          EXPECT_FALSE(pixel.ok());
        }
        continue;
      }
      ASSERT_TRUE(pixel.ok()) << pixel.message();
      const Eigen::Vector2d expected = (K * p_cam).hnormalized();
      EXPECT_LT((*pixel - expected).norm(), 1e-9 * (1.0 + expected.norm()));
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(FloorHomography, BackProjectionRecoversFloorPoints) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Matrix3d K = ReferenceK();
  const Eigen::Isometry3d T_base_cam = BaseFromCamera(ReferenceMount());
  const Eigen::Matrix3d H = FloorToImageHomography(T_base_cam, K);
  const Eigen::Matrix3d G = ImageToFloorHomography(H);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector2d floor = Eigen::Vector2d(1.5, 0.0) + core::DrawVector<2>(unit, rng);
    const core::Result<Eigen::Vector2d> pixel = ProjectFloorPoint(H, floor);
    ASSERT_TRUE(pixel.ok());
    const core::Result<Eigen::Vector2d> back = BackProjectPixel(G, *pixel);
    ASSERT_TRUE(back.ok()) << back.message();
    EXPECT_LT((*back - floor).norm(), 1e-12);
  }
}

TEST(FloorHomography, OpticalAxisMeetsTheFloorAtHeightOverTanPitch) {
  const CameraMount mount = ReferenceMount();
  const Eigen::Matrix3d K = ReferenceK();
  const Eigen::Matrix3d G =
      ImageToFloorHomography(FloorToImageHomography(BaseFromCamera(mount), K));
  const core::Result<Eigen::Vector2d> hit = BackProjectPixel(G, Eigen::Vector2d(K(0, 2), K(1, 2)));
  ASSERT_TRUE(hit.ok());
  const double expected_x_m = mount.height_m / std::tan(mount.pitch_rad) + mount.forward_m;
  EXPECT_NEAR(hit->x(), expected_x_m, 1e-12);  // 1.0540 m
  EXPECT_NEAR(hit->y(), 0.0, 1e-12);
}

TEST(FloorHomography, ImageRowsMapToTheExpectedGroundDistances) {
  // Down the central column, row v sees the floor at depression angle
  // pitch + atan((v - cy) / fy). For the reference camera this gives the
  // footprint from about 0.67 m (bottom row) to 2.2 m (top row) ahead of the axle.
  const CameraMount mount = ReferenceMount();
  const Eigen::Matrix3d K = ReferenceK();
  const Eigen::Matrix3d G =
      ImageToFloorHomography(FloorToImageHomography(BaseFromCamera(mount), K));
  for (double v : {0.0, 256.0, 700.0, 1023.0}) {
    const core::Result<Eigen::Vector2d> hit = BackProjectPixel(G, Eigen::Vector2d(K(0, 2), v));
    ASSERT_TRUE(hit.ok());
    const double depression_rad = mount.pitch_rad + std::atan((v - K(1, 2)) / K(1, 1));
    EXPECT_NEAR(hit->x(), mount.forward_m + mount.height_m / std::tan(depression_rad), 1e-12);
  }
  EXPECT_NEAR(BackProjectPixel(G, Eigen::Vector2d(640, 1023))->x(), 0.67, 0.01);
  EXPECT_NEAR(BackProjectPixel(G, Eigen::Vector2d(640, 0))->x(), 2.20, 0.02);
}

TEST(FloorHomography, PixelsOnOrAboveTheHorizonAreRejected) {
  CameraMount mount = ReferenceMount();
  mount.pitch_rad = 10.0 * kDeg;  // horizon inside the image
  const Eigen::Matrix3d K = ReferenceK();
  const Eigen::Matrix3d G =
      ImageToFloorHomography(FloorToImageHomography(BaseFromCamera(mount), K));
  const double horizon_v = K(1, 2) - K(1, 1) * std::tan(mount.pitch_rad);
  for (double u : {0.0, 640.0, 1279.0}) {
    EXPECT_FALSE(BackProjectPixel(G, Eigen::Vector2d(u, horizon_v - 1.0)).ok());
    EXPECT_FALSE(BackProjectPixel(G, Eigen::Vector2d(u, 0.0)).ok());
    const core::Result<Eigen::Vector2d> below =
        BackProjectPixel(G, Eigen::Vector2d(u, horizon_v + 1.0));
    ASSERT_TRUE(below.ok()) << below.message();
    EXPECT_GT(below->x(), 100.0);  // one row below the horizon is far away, but ahead
  }
  EXPECT_NE(BackProjectPixel(G, Eigen::Vector2d(640, 0)).message().find("horizon"),
            std::string::npos);
}

TEST(FloorHomography, FloorPointsBehindTheCameraAreRejected) {
  const Eigen::Matrix3d H = FloorToImageHomography(BaseFromCamera(ReferenceMount()), ReferenceK());
  EXPECT_FALSE(ProjectFloorPoint(H, Eigen::Vector2d(-2.0, 0.0)).ok());
  EXPECT_TRUE(ProjectFloorPoint(H, Eigen::Vector2d(1.0, 0.0)).ok());
}

TEST(FloorHomography, BackProjectionJacobianMatchesNumeric) {
  CameraMount mount = ReferenceMount();
  mount.roll_rad = 0.05;
  mount.yaw_rad = -0.1;
  const Eigen::Matrix3d G =
      ImageToFloorHomography(FloorToImageHomography(BaseFromCamera(mount), ReferenceK()));
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(640, 512), Eigen::Vector2d(10, 1000), Eigen::Vector2d(1200, 30)}) {
    Eigen::Matrix2d J;
    ASSERT_TRUE(BackProjectPixel(G, pixel, &J).ok());
    EXPECT_JACOBIAN_NEAR(
        J, [&](const Eigen::Vector2d& px) { return BackProjectPixel(G, px).value(); }, pixel, 1e-8);
  }
}

// MountFromFloorHomography inverts FloorToImageHomography (K = I) for any
// scale and sign of the matrix, on cameras looking down at the floor.
TEST(FloorHomography, MountFromFloorHomographyInvertsIt) {
  std::mt19937 rng(20261204);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    CameraMount mount = RandomMount(rng);
    mount.pitch_rad = 0.8 + 0.7 * unit(rng);  // 0.1 .. 1.5 rad down
    const Eigen::Isometry3d T_base_cam = BaseFromCamera(mount);
    // Where the optical axis meets the floor: in view.
    const Eigen::Vector3d axis = T_base_cam.linear().col(2);
    const Eigen::Vector3d centre = T_base_cam.translation();
    const Eigen::Vector2d in_view = (centre - axis * (centre.z() / axis.z())).head<2>();
    const double magnitude = std::exp(2.0 * unit(rng));
    const double scale = unit(rng) < 0.0 ? -magnitude : magnitude;
    const Eigen::Matrix3d H =
        scale * FloorToImageHomography(T_base_cam, Eigen::Matrix3d::Identity());
    const core::Result<CameraMount> back = MountFromFloorHomography(H, in_view);
    ASSERT_TRUE(back.ok()) << back.message();
    EXPECT_TRUE(SameMount(*back, mount, 1e-9))
        << "trial " << trial << ": height " << back->height_m << " vs " << mount.height_m;
  }
}

TEST(FloorHomography, MountFromFloorHomographyRejectsWhatIsNoFloorHomography) {
  const Eigen::Vector2d in_view(1.0, 0.0);
  Eigen::Matrix3d nan = Eigen::Matrix3d::Identity();
  nan(0, 2) = std::nan("");
  EXPECT_NE(MountFromFloorHomography(nan, in_view).message().find("not finite"), std::string::npos);
  EXPECT_NE(MountFromFloorHomography(Eigen::Matrix3d::Zero(), in_view).message().find("singular"),
            std::string::npos);
  // Floor axes of different units (y in thirds of a metre): no rigid camera.
  const Eigen::Matrix3d pixels =
      FloorToImageHomography(BaseFromCamera(ReferenceMount()), Eigen::Matrix3d::Identity()) *
      Eigen::Vector3d(1.0, 3.0, 1.0).asDiagonal();
  const core::Result<CameraMount> wrong = MountFromFloorHomography(pixels, {1.0, 0.0});
  EXPECT_FALSE(wrong.ok());
  EXPECT_NE(wrong.message().find("normalized image"), std::string::npos) << wrong.message();
}

}  // namespace
}  // namespace groundline::calibration
