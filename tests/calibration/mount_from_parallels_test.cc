#include "groundline/calibration/mount_from_parallels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "groundline/calibration/mount_remap.h"
#include "groundline/core/angles.h"

namespace groundline::calibration {
namespace {

using core::kDegToRad;
using core::kRadToDeg;

// A floor segment as the camera on `truth` sees it, measured under `used`
// (its BEV made with the wrong mount), endpoints with noise of sigma_m.
FloorSegment Seen(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const CameraMount& truth,
                  const CameraMount& used, double sigma_m, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, sigma_m);
  FloorSegment s;
  EXPECT_TRUE(RemapFloorPoint(a, truth, used, &s.start_m));
  EXPECT_TRUE(RemapFloorPoint(b, truth, used, &s.end_m));
  const Eigen::Vector2d d = (s.end_m - s.start_m).normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  s.start_m += noise(*rng) * n;
  s.end_m += noise(*rng) * n;
  const double length = (s.end_m - s.start_m).norm();
  s.covariance << sigma_m * sigma_m, 0.0, 0.0, 2.0 * sigma_m * sigma_m / (length * length);
  return s;
}

// An aisle with its two tape edges 1.2 m apart, a joint between them and a
// stop bar across, in three images taken at different places: the start
// mount 3 deg off in pitch and 0.4 deg in roll, the truth recovered.
TEST(MountFromParallels, RecoversPitchAndRollFromAnAisleSeenThreeDegreesOff) {
  CameraMount truth;
  truth.pitch_rad = 40.0 * kDegToRad;
  truth.roll_rad = 0.3 * kDegToRad;
  CameraMount start = truth;
  start.pitch_rad += 3.0 * kDegToRad;
  start.roll_rad -= 0.4 * kDegToRad;
  std::mt19937 rng(11);
  std::vector<ParallelImage> images;
  for (const double shift : {0.0, 0.25, -0.2}) {
    ParallelImage image;
    image.name = "view" + std::to_string(images.size());
    image.mount_used = start;
    for (const double y : {-0.6 + shift, 0.6 + shift, 0.05 + shift}) {
      image.segments.push_back(Seen({0.7, y}, {2.3, y}, truth, start, 0.002, &rng));
    }
    image.segments.push_back(
        Seen({1.4 + shift, -0.5}, {1.4 + shift, 0.5}, truth, start, 0.002, &rng));
    images.push_back(image);
  }
  const core::Result<MountFromParallels> solved =
      SolveMountFromParallels(images, start, MountFromParallelsOptions{});
  ASSERT_TRUE(solved.ok()) << solved.message();
  // Before: the parallel edges several degrees apart.
  EXPECT_GT(MaxOffDeg(solved->pairs_before), 3.0);
  EXPECT_EQ(solved->pairs_before.size(), 9u);  // 3 images x (2 parallel + 1 perpendicular)
  EXPECT_NEAR(solved->mount.pitch_rad * kRadToDeg, truth.pitch_rad * kRadToDeg, 0.05);
  EXPECT_NEAR(solved->mount.roll_rad * kRadToDeg, truth.roll_rad * kRadToDeg, 0.1);
  EXPECT_LT(MaxOffDeg(solved->pairs_after), 0.3);
  EXPECT_EQ(solved->pairs_after.size(), 9u);
  // Height and yaw are not observable here and stay as given.
  EXPECT_EQ(solved->mount.height_m, start.height_m);
  EXPECT_EQ(solved->mount.yaw_rad, start.yaw_rad);
  // The sigmas cover the errors and are not the priors'.
  const double pitch_sigma_deg = std::sqrt(solved->covariance(0, 0)) * kRadToDeg;
  EXPECT_GT(pitch_sigma_deg, 0.0);
  EXPECT_LT(pitch_sigma_deg, 0.1);
  EXPECT_LT(std::abs(solved->mount.pitch_rad - truth.pitch_rad) * kRadToDeg,
            4.0 * pitch_sigma_deg + 0.01);
  EXPECT_LT(std::sqrt(solved->covariance(1, 1)) * kRadToDeg, 0.9);
}

// An oblique line (45 deg) is neither parallel nor perpendicular: no pair.
TEST(MountFromParallels, ObliqueLinesAloneAreRefusedWithTheReason) {
  const CameraMount mount;
  ParallelImage image;
  image.name = "oblique";
  image.mount_used = mount;
  FloorSegment a, b;
  a.start_m = {0.8, -0.5};
  a.end_m = {2.2, -0.5};
  b.start_m = {0.8, 0.0};
  b.end_m = {1.8, 1.0};
  image.segments = {a, b};
  const core::Result<MountFromParallels> solved =
      SolveMountFromParallels({image}, mount, MountFromParallelsOptions{});
  ASSERT_FALSE(solved.ok());
  EXPECT_NE(solved.message().find("no image has two floor lines parallel or perpendicular"),
            std::string::npos)
      << solved.message();
  MountFromParallelsOptions bad;
  bad.parallel_tolerance_deg = 50.0;
  EXPECT_NE(SolveMountFromParallels({image}, mount, bad).message().find("parallel_tolerance_deg"),
            std::string::npos);
}

}  // namespace
}  // namespace groundline::calibration
