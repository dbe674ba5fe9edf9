#include "groundline/calibration/ground_homography.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/floor_projection.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "jacobian_check.h"
#include "test_cameras.h"
#include "test_data.h"
#include "test_units.h"

namespace groundline::calibration {
namespace {

using ::groundline::testing::kDeg;
using ::groundline::testing::kPi;

CameraMount TiltedMount() {
  CameraMount mount;
  mount.height_m = 0.31;
  mount.pitch_rad = 33.0 * kDeg;
  mount.roll_rad = 1.5 * kDeg;
  mount.yaw_rad = -2.0 * kDeg;
  mount.forward_m = 0.12;
  mount.lateral_m = 0.01;
  return mount;
}

std::string Flat(const Eigen::Matrix3d& H) {
  std::ostringstream out;
  out.precision(17);
  out << "[";
  for (int i = 0; i < 9; ++i) out << (i ? ", " : "") << H(i / 3, i % 3);
  return out.str() + "]";
}

// The sign rule of the header: with the camera above a right-handed z-up floor,
// the image-to-floor homography that gives lambda > 0 has det < 0.
TEST(GroundHomographySign, FloorToImageInverseHasNegativeDeterminant) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Matrix3d K = test_cameras::AllTestCameras()[0].K();
  for (int i = 0; i < 200; ++i) {
    CameraMount mount;
    mount.height_m = 0.5 + 0.4 * unit(rng);
    mount.pitch_rad = 1.5 * unit(rng);
    mount.roll_rad = kPi * unit(rng);
    mount.yaw_rad = kPi * unit(rng);
    const Eigen::Matrix3d H_img_floor = FloorToImageHomography(BaseFromCamera(mount), K);
    EXPECT_LT(ImageToFloorHomography(H_img_floor).determinant(), 0.0);
  }
}

// A legacy file holding -3.7 H_floor_img (scale and sign are free) reads back
// normalized so that BackProjectPixel accepts floor pixels and finds the point.
TEST(GroundHomographyYaml, LegacyFileIsSignNormalized) {
  const Eigen::Matrix3d K = test_cameras::AllTestCameras()[0].K();
  const Eigen::Matrix3d H_img_floor = FloorToImageHomography(BaseFromCamera(TiltedMount()), K);
  const Eigen::Matrix3d H_floor_img = ImageToFloorHomography(H_img_floor);
  core::Result<GroundHomography> read =
      ParseGroundHomographyYaml("homography: " + Flat(-3.7 * H_floor_img) + "\n", "robot.yaml");
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->input, HomographyInput::kRectifiedPixel);
  EXPECT_TRUE(read->floor_frame_right_handed);
  const Eigen::Vector2d floor_m(1.1, -0.2);
  const Eigen::Vector2d pixel = *ProjectFloorPoint(H_img_floor, floor_m);
  core::Result<Eigen::Vector2d> back = BackProjectPixel(read->H_floor_input, pixel);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_LT((*back - floor_m).norm(), 1e-12);
}

// Version 2 maps normalized image coordinates; through a distorted camera it
// must agree with FloorProjection of the same mount.
TEST(GroundHomographyYaml, VersionTwoThroughADistortedCameraMatchesFloorProjection) {
  const CameraModel camera = test_cameras::AllTestCameras()[4];  // OPENCV8
  const Eigen::Isometry3d T_base_cam = BaseFromCamera(TiltedMount());
  const Eigen::Matrix3d H_floor_norm =
      ImageToFloorHomography(FloorToImageHomography(T_base_cam, Eigen::Matrix3d::Identity()));
  core::Result<GroundHomography> read = ParseGroundHomographyYaml(
      "version: '2'\ndate: '2024-01-02T03:04:05'\nhomography: " + Flat(-2.0 * H_floor_norm) + "\n",
      "v2.yaml");
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->input, HomographyInput::kNormalizedImage);
  EXPECT_TRUE(read->floor_frame_right_handed);
  EXPECT_EQ(read->date, "2024-01-02T03:04:05");
  const FloorProjection projection(camera, T_base_cam);
  const Eigen::Matrix3d H = FloorFromNormalizedImage(*read, Eigen::Matrix3d::Identity());
  std::mt19937 rng(32);
  int checked = 0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector2d pixel = test_cameras::RandomPixel(camera, rng);
    core::Result<Eigen::Vector2d> expected = projection.FloorPointOfPixel(pixel);
    core::Result<Eigen::Vector2d> floor = FloorPointOfPixel(camera, H, pixel);
    ASSERT_EQ(expected.ok(), floor.ok());
    if (!floor.ok()) continue;
    ++checked;
    EXPECT_LT((*floor - *expected).norm(), 1e-9 * (1.0 + expected->norm()));
    Eigen::Matrix2d J;
    ASSERT_TRUE(FloorPointOfPixel(camera, H, pixel, &J).ok());
    const auto f = [&](const Eigen::Vector2d& kilo_px) -> Eigen::Vector2d {
      return 1000.0 * *FloorPointOfPixel(camera, H, 1000.0 * kilo_px);  // mm
    };
    const Eigen::Matrix2d J_scaled = 1e6 * J;
    EXPECT_JACOBIAN_NEAR(J_scaled, f, Eigen::Vector2d(pixel / 1000.0), 1e-6);
  }
  EXPECT_GT(checked, 100);
}

TEST(GroundHomographyYaml, MalformedFilesNameTheFileAndKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"other: 1\n", "missing key 'homography'"},
      {"homography: [1, 2, 3, 4, 5, 6, 7, 8]\n",
       "bad.yaml:1: key 'homography': expected 9 numbers"},
      {"homography: [1, 0, 0, 0, 1, 0, 0, x, 1]\n", "element 7: expected a finite number, got 'x'"},
      {"homography: [1, 2, 3, 2, 4, 6, 0, 0, 0]\n", "singular"},
      {"version: '3'\nhomography: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n", "key 'version': expected '2'"},
      {"version: '2'\nformat: resolution-independent\nhomography: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n",
       "are not supported"},
      {"homography: [1, 0\n", "YAML syntax error"},
  };
  for (const auto& [text, expected] : cases) {
    core::Result<GroundHomography> read = ParseGroundHomographyYaml(text, "bad.yaml");
    ASSERT_FALSE(read.ok()) << text;
    EXPECT_NE(read.message().find(expected), std::string::npos) << read.message();
    EXPECT_NE(read.message().find("bad.yaml"), std::string::npos) << read.message();
  }
}

// The real per-robot files: H_floor_input * P is, up to scale, [r1 r2 t] of a
// camera about 0.1 m above the floor looking ahead; the bottom of the raw image
// sees the floor 5-30 cm ahead of the axle, straight ahead.
TEST(RealGroundHomography, DuckietownRobotFilesArePlausible) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown/robot_calibrations");
  const std::filesystem::path root =
      groundline::testing::SharedDataDir() / "floor/duckietown/robot_calibrations";
  for (const char* robot : {"default", "milo", "tori", "kitt", "tesla"}) {
    core::Result<GroundHomography> h =
        ReadGroundHomographyYaml(root / "camera_extrinsic" / (std::string(robot) + ".yaml"));
    ASSERT_TRUE(h.ok()) << h.message();
    core::Result<RosCameraInfo> info =
        ReadRosCameraInfo(root / "camera_intrinsic" / (std::string(robot) + ".yaml"));
    ASSERT_TRUE(info.ok()) << info.message();
    const Eigen::Matrix3d P = info->projection.leftCols<3>();
    const Eigen::Matrix3d H_floor_norm = FloorFromNormalizedImage(*h, P);
    Eigen::Matrix3d G = H_floor_norm.inverse();  // ~ s [r1 r2 t], s > 0
    const double s = 0.5 * (G.col(0).norm() + G.col(1).norm());
    EXPECT_NEAR(G.col(0).norm() / G.col(1).norm(), 1.0, 0.1) << robot;
    G /= s;
    EXPECT_LT(std::abs(G.col(0).dot(G.col(1))), 0.06) << robot;
    Eigen::Matrix3d R_cam_floor;
    R_cam_floor << G.col(0), G.col(1), G.col(0).cross(G.col(1));
    const Eigen::Vector3d centre_m = -R_cam_floor.transpose() * G.col(2);
    EXPECT_GT(centre_m.z(), 0.07) << robot;  // above the floor
    EXPECT_LT(centre_m.z(), 0.14) << robot;
    EXPECT_GT(centre_m.x(), 0.0) << robot;  // ahead of the axle
    EXPECT_LT(centre_m.x(), 0.15) << robot;
    EXPECT_LT(std::abs(centre_m.y()), 0.02) << robot;

    double previous_x_m = 0.0;
    for (double v : {470.0, 400.0, 330.0, 280.0}) {  // up the raw image's centre column
      core::Result<Eigen::Vector2d> floor =
          FloorPointOfPixel(info->camera, H_floor_norm, {320.0, v});
      ASSERT_TRUE(floor.ok()) << robot << ": " << floor.message();
      EXPECT_GT(floor->x(), previous_x_m) << robot;
      EXPECT_LT(std::abs(floor->y()), 0.05) << robot;
      previous_x_m = floor->x();
    }
    core::Result<Eigen::Vector2d> bottom =
        FloorPointOfPixel(info->camera, H_floor_norm, {320.0, 470.0});
    EXPECT_GT(bottom->x(), 0.05) << robot;
    EXPECT_LT(bottom->x(), 0.30) << robot;
    EXPECT_FALSE(FloorPointOfPixel(info->camera, H_floor_norm, {320.0, 5.0}).ok()) << robot;  // sky
  }
}

// dd24: the board corners in the raw image land on the 17 mm board grid, and
// the arrow taped on the floor in front of the board maps plausibly.
TEST(RealGroundHomography, Dd24BoardCornersLandOnTheGridAndTheArrowBeforeTheBoard) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown/extrinsics/dd24/real-world/scenario0");
  const std::filesystem::path dir = groundline::testing::SharedDataDir() /
                                    "floor/duckietown/extrinsics/dd24/real-world/scenario0";
  core::Result<GroundHomography> h = ReadGroundHomographyYaml(dir / "homography.yaml");
  ASSERT_TRUE(h.ok()) << h.message();
  EXPECT_EQ(h->input, HomographyInput::kNormalizedImage);
  EXPECT_FALSE(h->floor_frame_right_handed);  // the board frame: x right, y towards the camera
  core::Result<RosCameraInfo> info = ReadRosCameraInfo(dir / "calibration-intrinsic-dd24.yaml");
  ASSERT_TRUE(info.ok()) << info.message();
  const Eigen::Matrix3d H = FloorFromNormalizedImage(*h, Eigen::Matrix3d::Identity());

  const cv::Mat image = cv::imread((dir / "image-0.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  std::vector<cv::Point2f> corners;
  ASSERT_TRUE(cv::findChessboardCornersSB(image, cv::Size(7, 5), corners));
  constexpr double kSquareM = 0.017;
  std::set<std::pair<long, long>> nodes;
  for (const cv::Point2f& corner : corners) {
    core::Result<Eigen::Vector2d> floor = FloorPointOfPixel(info->camera, H, {corner.x, corner.y});
    ASSERT_TRUE(floor.ok()) << floor.message();
    const Eigen::Vector2d node = (*floor / kSquareM).array().round();
    EXPECT_LT((*floor - kSquareM * node).norm(), 0.003);
    nodes.insert({std::lround(node.x()), std::lround(node.y())});
  }
  EXPECT_EQ(nodes.size(), 35u);
  EXPECT_EQ(nodes.begin()->first, 0);  // columns 0..6, rows 0..4 of the board
  EXPECT_EQ(nodes.rbegin()->first, 6);

  // The taped arrow below the board (tip near pixel (233, 392)): on the board's
  // centre line (x = 3 squares), between 4 and 10 cm nearer than its last row,
  // and nearer still further down the image.
  double previous_y_m = 4 * kSquareM;
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(233, 392), Eigen::Vector2d(236, 450), Eigen::Vector2d(231, 520)}) {
    core::Result<Eigen::Vector2d> floor = FloorPointOfPixel(info->camera, H, pixel);
    ASSERT_TRUE(floor.ok()) << floor.message();
    EXPECT_NEAR(floor->x(), 3 * kSquareM, 0.005);
    EXPECT_GT(floor->y(), previous_y_m + 0.005);
    EXPECT_LT(floor->y(), 4 * kSquareM + 0.10);
    previous_y_m = floor->y();
  }
  EXPECT_FALSE(FloorPointOfPixel(info->camera, H, {240.0, 60.0}).ok());  // above the horizon
}

// The mount decomposed from the real per-robot files: a camera about 0.1 m
// high, 0-15 cm ahead of the axle, pitched down, whose floor points agree with
// the homography's over the lower image (the files' columns are up to 10 % off
// a rotation's, so within a few millimetres, not exactly).
TEST(RealGroundHomography, DuckietownRobotFilesGiveTheirMount) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown/robot_calibrations");
  const std::filesystem::path root =
      groundline::testing::SharedDataDir() / "floor/duckietown/robot_calibrations";
  for (const char* robot : {"default", "milo", "tori", "kitt", "tesla"}) {
    core::Result<GroundHomography> h =
        ReadGroundHomographyYaml(root / "camera_extrinsic" / (std::string(robot) + ".yaml"));
    ASSERT_TRUE(h.ok()) << h.message();
    core::Result<RosCameraInfo> info =
        ReadRosCameraInfo(root / "camera_intrinsic" / (std::string(robot) + ".yaml"));
    ASSERT_TRUE(info.ok()) << info.message();
    const Eigen::Matrix3d P = info->projection.leftCols<3>();
    core::Result<GroundHomographyMount> mount = MountFromGroundHomography(*h, P);
    ASSERT_TRUE(mount.ok()) << robot << ": " << mount.message();
    EXPECT_FALSE(mount->mirrored_y);
    const CameraMount& m = mount->mount;
    EXPECT_GT(m.height_m, 0.07) << robot;
    EXPECT_LT(m.height_m, 0.14) << robot;
    EXPECT_GT(m.forward_m, 0.0) << robot;
    EXPECT_LT(m.forward_m, 0.15) << robot;
    EXPECT_GT(m.pitch_rad, 5.0 * kDeg) << robot;
    EXPECT_LT(m.pitch_rad, 40.0 * kDeg) << robot;
    const Eigen::Matrix3d H_floor_norm = FloorFromNormalizedImage(*h, P);
    const Eigen::Matrix3d H_floor_norm_of_mount = ImageToFloorHomography(
        FloorToImageHomography(BaseFromCamera(m), Eigen::Matrix3d::Identity()));
    for (double v : {470.0, 420.0, 370.0}) {
      for (double u : {120.0, 320.0, 520.0}) {
        core::Result<Eigen::Vector2d> by_file =
            FloorPointOfPixel(info->camera, H_floor_norm, {u, v});
        core::Result<Eigen::Vector2d> by_mount =
            FloorPointOfPixel(info->camera, H_floor_norm_of_mount, {u, v});
        ASSERT_TRUE(by_file.ok() && by_mount.ok()) << robot;
        EXPECT_LT((*by_file - *by_mount).norm(), 0.1 * by_file->norm())
            << robot << " pixel " << u << ", " << v << ": " << by_file->transpose() << " vs "
            << by_mount->transpose();
      }
    }
  }
}

// dd24's version-2 file maps to the board frame, left-handed: the mount comes
// with y mirrored, and its floor points are the file's mirrored, to 3 mm on the
// board's corners.
TEST(RealGroundHomography, Dd24VersionTwoGivesAMountInTheMirroredBoardFrame) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown/extrinsics/dd24/real-world/scenario0");
  const std::filesystem::path dir = groundline::testing::SharedDataDir() /
                                    "floor/duckietown/extrinsics/dd24/real-world/scenario0";
  core::Result<GroundHomography> h = ReadGroundHomographyYaml(dir / "homography.yaml");
  ASSERT_TRUE(h.ok()) << h.message();
  core::Result<RosCameraInfo> info = ReadRosCameraInfo(dir / "calibration-intrinsic-dd24.yaml");
  ASSERT_TRUE(info.ok()) << info.message();
  core::Result<GroundHomographyMount> mount = MountFromGroundHomography(*h, info->camera.K());
  ASSERT_TRUE(mount.ok()) << mount.message();
  EXPECT_TRUE(mount->mirrored_y);
  EXPECT_GT(mount->mount.height_m, 0.05);
  EXPECT_LT(mount->mount.height_m, 0.20);
  const Eigen::Matrix3d H_file = FloorFromNormalizedImage(*h, Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d H_mount = ImageToFloorHomography(
      FloorToImageHomography(BaseFromCamera(mount->mount), Eigen::Matrix3d::Identity()));
  const cv::Mat image = cv::imread((dir / "image-0.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  std::vector<cv::Point2f> corners;
  ASSERT_TRUE(cv::findChessboardCornersSB(image, cv::Size(7, 5), corners));
  for (const cv::Point2f& corner : corners) {
    core::Result<Eigen::Vector2d> by_file =
        FloorPointOfPixel(info->camera, H_file, {corner.x, corner.y});
    core::Result<Eigen::Vector2d> by_mount =
        FloorPointOfPixel(info->camera, H_mount, {corner.x, corner.y});
    ASSERT_TRUE(by_file.ok() && by_mount.ok());
    EXPECT_LT((Eigen::Vector2d(by_file->x(), -by_file->y()) - *by_mount).norm(), 0.003)
        << by_file->transpose() << " vs " << by_mount->transpose();
  }
}

}  // namespace
}  // namespace groundline::calibration
