// Real-camera check on the Duckietown extrinsic-calibration scenario: the
// ground homography comes from the floor chessboard of frame0 (the way
// Duckietown calibrates it), is turned into a camera mount, and the road of
// frame1, seen by the same camera, is extracted in the BEV. The road's
// painted lines (white edge, yellow dashed centre line), parallel on the
// floor, must come out parallel within 1 deg. Parallelism does not depend on
// the board's (unknown) square size; 31 mm is assumed for metres.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "groundline/calibration/camera_model.h"
#include "groundline/core/angles.h"
#include "groundline/perception/mount_parallel_check.h"
#include "groundline/perception/line_extractor.h"
#include "test_data.h"

namespace groundline::perception {
namespace {

constexpr double kSquareM = 0.031;

// cameras.yaml: camera_matrix and plumb_bob distortion of map_0/vehicle_0/camera_0.
calibration::CameraModel DuckieCamera() {
  return *calibration::CameraModel::Create(
      "LENSMODEL_OPENCV5",
      {295.79606866959824, 299.5389048862878, 321.2621599038631, 241.73616515312332,
       -0.23543978771661125, 0.03637781479419574, -0.0033069818601306755, -0.0012140708179525926,
       0.0},
      640, 480);
}

// The camera's mount from the floor chessboard of frame0 (the way Duckietown
// calibrates it), base_link under the camera with x along the optical axis.
std::optional<calibration::CameraMount> BoardMount(const calibration::CameraModel& camera,
                                                  const std::filesystem::path& dir) {
  const cv::Mat board = cv::imread((dir / "frame0_distorted.jpg").string(), cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(board.empty());
  if (board.empty()) return std::nullopt;
  std::vector<cv::Point2f> corners;
  cv::Size pattern;
  for (const cv::Size size : {cv::Size(7, 4), cv::Size(4, 7), cv::Size(7, 5), cv::Size(6, 4)}) {
    if (cv::findChessboardCornersSB(board, size, corners)) {
      pattern = size;
      break;
    }
  }
  EXPECT_FALSE(corners.empty()) << "no chessboard in frame0";
  if (corners.empty()) return std::nullopt;
  std::vector<cv::Point2f> normalized, floor;
  for (size_t i = 0; i < corners.size(); ++i) {
    core::Result<Eigen::Vector3d> ray = camera.Unproject({corners[i].x, corners[i].y});
    if (!ray.ok()) return std::nullopt;
    normalized.emplace_back(ray->x() / ray->z(), ray->y() / ray->z());
    floor.emplace_back(kSquareM * (i % pattern.width), kSquareM * (i / pattern.width));
  }
  // G = H_norm_board ~ s [r1 r2 t]: the board's pose in the camera.
  cv::Mat H = cv::findHomography(floor, normalized);
  Eigen::Matrix3d G;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) G(r, c) = H.at<double>(r, c);
  G /= 0.5 * (G.col(0).norm() + G.col(1).norm());
  if (G(2, 2) < 0) G = -G;  // the board is in front of the camera
  Eigen::Matrix3d R;
  R.col(0) = G.col(0).normalized();
  R.col(1) = (G.col(1) - R.col(0).dot(G.col(1)) * R.col(0)).normalized();
  R.col(2) = R.col(0).cross(R.col(1));
  Eigen::Isometry3d T_cam_board = Eigen::Isometry3d::Identity();
  T_cam_board.linear() = R;
  T_cam_board.translation() = G.col(2);
  Eigen::Isometry3d T_board_cam = T_cam_board.inverse();
  if (T_board_cam.translation().z() < 0) {  // board z down: flip to z up (x stays, y flips)
    Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
    flip.linear().diagonal() << 1, -1, -1;
    T_board_cam = flip * T_board_cam;
  }
  // base_link: under the camera, x along the optical axis projected on the floor.
  const Eigen::Vector3d c = T_board_cam.translation();
  Eigen::Vector3d forward = T_board_cam.linear().col(2);
  forward.z() = 0.0;
  forward.normalize();
  Eigen::Isometry3d T_board_base = Eigen::Isometry3d::Identity();
  T_board_base.linear().col(0) = forward;
  T_board_base.linear().col(1) = Eigen::Vector3d::UnitZ().cross(forward);
  T_board_base.linear().col(2) = Eigen::Vector3d::UnitZ();
  T_board_base.translation() << c.x(), c.y(), 0.0;
  const core::Result<calibration::CameraMount> mount =
      calibration::MountFromBaseCamera(T_board_base.inverse() * T_board_cam);
  EXPECT_TRUE(mount.ok()) << mount.message();
  if (!mount.ok()) return std::nullopt;
  return *mount;
}

TEST(DuckietownBev, ParallelRoadLinesStayParallel) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown/extrinsics/scenario0");
  const std::filesystem::path dir =
      ::groundline::testing::SharedDataDir() / "floor/duckietown/extrinsics/scenario0";
  const calibration::CameraModel camera = DuckieCamera();
  const std::optional<calibration::CameraMount> mount = BoardMount(camera, dir);
  ASSERT_TRUE(mount.has_value());
  // A Duckiebot camera: about 10 cm above the floor, pitched down 10-20 deg.
  EXPECT_NEAR(mount->height_m, 0.10, 0.03);
  EXPECT_GT(mount->pitch_rad, 10.0 * std::numbers::pi / 180);
  EXPECT_LT(mount->pitch_rad, 20.0 * std::numbers::pi / 180);

  BevRemap::Options options;
  options.grid = {0.15, 0.75, -0.3, 0.3, 0.0025};
  options.supersampling = 2;  // as groundline extract: 2 along x 4 across
  options.supersampling_across = 4;
  const BevRemap remap(camera, *mount, options);
  const cv::Mat road = cv::imread((dir / "frame1_distorted.jpg").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(road.empty());
  cv::Mat bev;
  remap.Apply(road, &bev);
  cv::imwrite((::groundline::testing::ScratchDir("duckietown") / "bev.png").string(), bev);
  LineExtractorOptions extract;
  extract.dark = false;
  extract.min_line_length_m = 0.08;
  // The white edge line is 4.5 cm wide, 18 cells: wider than the ridge, so
  // it is found as a bar of two facing edges, whose ridges lie on its inner
  // flanks 2-3 cm apart (the default least bar width is for warehouse bars at
  // 1 cm cells).
  extract.bar_min_width_m = 0.015;
  const LineExtractor extractor(remap, extract);
  const LineExtraction out = extractor.Extract(bev);
  // The white edge on the right and the yellow centre dashes on the left.
  ASSERT_EQ(out.lines.size(), 2u);
  const ExtractedLine& a = out.lines[0];
  const ExtractedLine& b = out.lines[1];
  const double angle_deg = std::asin(std::abs(a.line.Normal().x() * b.line.Normal().y() -
                                              a.line.Normal().y() * b.line.Normal().x())) *
                           180.0 / std::numbers::pi;
  EXPECT_LT(angle_deg, 1.0);
  RecordProperty("angle_between_lines_deg", std::to_string(angle_deg));
  EXPECT_EQ(a.kind.orientation, LineOrientation::kLongitudinal);
  EXPECT_EQ(b.kind.orientation, LineOrientation::kLongitudinal);
  // On opposite sides of the camera, a lane (0.2-0.35 m at 31 mm squares) apart.
  const double y_a = a.line.rho_m * a.line.Normal().y();
  const double y_b = b.line.rho_m * b.line.Normal().y();
  EXPECT_LT(y_a * y_b, 0.0);
  EXPECT_GT(std::abs(y_a - y_b), 0.2);
  EXPECT_LT(std::abs(y_a - y_b), 0.35);
}

// The self-calibration's single-image check on the real road of frame1: from
// the board's mount with 3 deg more pitch, which turns the road's parallel
// edges several degrees apart, the solved pitch makes them parallel again
// within 0.5 deg, measured on a new extraction under the solved mount, and
// lands within 0.5 deg of the board's (measured: 0.02 deg from either side).
// The dashes of the centre line are short in the view (4 cm least length).
TEST(DuckietownBev, SelfCalibratedPitchMakesTheRoadEdgesParallelFromThreeDegreesOff) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown/extrinsics/scenario0");
  const std::filesystem::path dir =
      ::groundline::testing::SharedDataDir() / "floor/duckietown/extrinsics/scenario0";
  const calibration::CameraModel camera = DuckieCamera();
  const std::optional<calibration::CameraMount> board = BoardMount(camera, dir);
  ASSERT_TRUE(board.has_value());
  for (const double off_deg : {3.0, -3.0}) {
    SCOPED_TRACE("start pitch off by " + std::to_string(off_deg) + " deg");
    calibration::CameraMount start = *board;
    start.pitch_rad += off_deg * core::kDegToRad;
    MountParallelCheckOptions options;
    options.bev.grid = {0.15, 0.75, -0.3, 0.3, 0.0025};
    options.extractor.dark = false;
    options.extractor.min_line_length_m = 0.04;
    options.extractor.bar_min_width_m = 0.015;  // the 4.5 cm white line, as above
    const cv::Mat road =
        cv::imread((dir / "frame1_distorted.jpg").string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(road.empty());
    const core::Result<MountParallelCheck> check =
        CheckMountByParallels({{"frame1", road}}, camera, start, options);
    ASSERT_TRUE(check.ok()) << check.message();
    ASSERT_FALSE(check->measured_before.empty());
    ASSERT_FALSE(check->measured_after.empty());
    const double before = calibration::MaxOffDeg(check->measured_before);
    const double after = calibration::MaxOffDeg(check->measured_after);
    RecordProperty("off_before_deg", std::to_string(before));
    RecordProperty("off_after_deg", std::to_string(after));
    EXPECT_GT(before, 3.0);
    EXPECT_LT(after, 0.5);
    EXPECT_NEAR(check->solution.mount.pitch_rad * core::kRadToDeg,
                board->pitch_rad * core::kRadToDeg, 0.5);
    EXPECT_LT(std::sqrt(check->solution.covariance(0, 0)) * core::kRadToDeg, 0.5);
    std::printf("start %+.1f deg: lines off %.2f deg before, %.2f after; pitch %.3f (board %.3f) "
                "+- %.3f deg\n",
                off_deg, before, after, check->solution.mount.pitch_rad * core::kRadToDeg,
                board->pitch_rad * core::kRadToDeg,
                std::sqrt(check->solution.covariance(0, 0)) * core::kRadToDeg);
  }
}

}  // namespace
}  // namespace groundline::perception
