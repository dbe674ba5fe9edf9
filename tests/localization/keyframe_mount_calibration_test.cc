// The self-calibration beside the localizer (keyframe_mount_calibration.h):
// the bird's-eye view follows the estimate in bounded steps at a bounded
// rate, never jumps, and the estimate stays right while the frames come
// under the mounts it applied. The camera front end rebuilt for another
// mount (FloorFrontEnd::WithMount) reads a real rendered floor where the
// commissioned mount misplaces it, and carries the mount's uncertainty into
// the lines' covariances.
#include "groundline/localization/keyframe_mount_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "synthetic_aisle.h"
#include "groundline/calibration/mount_remap.h"
#include "groundline/core/angles.h"
#include "groundline/localization/floor_front_end.h"

namespace groundline::localization {
namespace {

using calibration::CameraMount;
using calibration::kMountHeight;
using calibration::kMountPitch;
using calibration::kMountRoll;
using calibration::kMountYaw;
using calibration::MountVector;
using core::kDegToRad;
using core::kRadToDeg;
using testing_aisle::Aisle;
using testing_aisle::Difference;
using testing_aisle::Drive;
using testing_aisle::MakeFrame;
using testing_aisle::Moved;

KeyframeOutput KeyframeOf(const calibration::MountFrame& f) {
  KeyframeOutput k;
  k.stamp_s = f.stamp_s;
  k.frame_stamp_s = f.stamp_s;
  k.T_odom_base = f.T_odom_base;
  k.floor.stamp_s = f.stamp_s;
  k.floor.camera_mount = f.mount_used;
  for (const calibration::FloorSegment& s : f.segments) {
    LineObservation line;
    line.endpoint_a_base_m = s.start_m;
    line.endpoint_b_base_m = s.end_m;
    line.line_base = perception::LineFromPoints(s.start_m, s.end_m).value();
    // As FloorFrontEnd::WithMount gives it: the applied mount's uncertainty
    // on top of perception's (about 2 cm across the line), which the
    // self-calibration must take out again.
    line.mount_covariance = Eigen::Vector2d(4e-4, 1e-4).asDiagonal();
    line.covariance = s.covariance + line.mount_covariance;
    k.floor.lines.push_back(line);
  }
  return k;
}

// A payload pitches the camera 1 deg down and lowers it 5 mm at 10 s and is
// taken off at 30 s. The BEV (frames made under the applied mount) follows
// in steps of at most max_step, at most one per min_interval_s, is on the
// loaded mount before the unloading and back on the commissioned one at the
// end; the estimate is not disturbed by the frames' changing mount. The
// observations are expressed under the best estimate at each update: while a
// window or frame pair is held as a possible step, under the mount it showed
// with its covariance (handed out at once, the BEV unchanged), otherwise
// under the estimate's components that follow it.
TEST(KeyframeMountCalibration, TheBevFollowsAPayloadInBoundedSteps) {
  Drive d;
  d.world = Aisle(200.0);
  const CameraMount commissioned;
  const CameraMount loaded = Moved(commissioned, 1.0, 0.0, -5.0, 0.0);
  const MountApplyOptions apply;
  KeyframeMountCalibration cal(commissioned, calibration::MountSelfCalibrationOptions{}, apply);
  CameraMount bev_mount = commissioned;
  CameraMount observed = commissioned;
  std::vector<double> update_stamps;  // of the updates that moved the BEV
  int updates = 0, suspicion_updates = 0;
  std::vector<double> suspected_at;  // the first update of each suspicion
  bool suspected = false;
  std::optional<CameraMount> bev_when_unloaded;
  for (double t = 0.0; t < 50.0; t += 1.0 / d.rate_hz) {
    const CameraMount truth = t < 10.0 || t >= 30.0 ? commissioned : loaded;
    if (t >= 30.0 && !bev_when_unloaded) bev_when_unloaded = bev_mount;
    cal.AddKeyframe(KeyframeOf(MakeFrame(d, t, truth, bev_mount)));
    const calibration::MountEstimate& e = cal.estimate();
    const auto update = cal.DueMountUpdate(t);
    // A suspicion's coming and going is handed out at the keyframe it came,
    // and an update that leaves both mounts where they were is one of them.
    const bool suspicion_changed = e.step_suspected != suspected;
    if (suspicion_changed) {
      EXPECT_TRUE(update.has_value()) << "t " << t;
    }
    if (update && SameMount(update->mount, bev_mount, 0.0) &&
        SameMount(update->observed, observed, 0.0)) {
      EXPECT_TRUE(suspicion_changed) << "t " << t;
    }
    if (!update) continue;
    ++updates;
    if (suspicion_changed) ++suspicion_updates;
    EXPECT_TRUE(SameMount(update->mount, cal.applied()));
    EXPECT_TRUE(SameMount(update->observed, cal.observed()));
    for (int i = 0; i < 4; ++i) EXPECT_GE(update->covariance(i, i), 0.0);
    const MountVector observed_components = calibration::MountComponents(update->observed);
    if (e.step_suspected) {
      // Under the mount the suspect showed, with its covariance; while the
      // payload is on, that holds the loaded mount.
      EXPECT_TRUE(observed_components.isApprox(e.suspected_components, 1e-12)) << "t " << t;
      EXPECT_TRUE(update->covariance.isApprox(e.suspected_covariance, 1e-12)) << "t " << t;
      if (t > 10.0 && t < 30.0) {
        const MountVector off = observed_components - calibration::MountComponents(loaded);
        for (int i : {kMountPitch, kMountHeight}) {
          EXPECT_LT(std::abs(off(i)), 3.0 * std::sqrt(update->covariance(i, i)))
              << "t " << t << " component " << i;
        }
      }
      if (!suspected) suspected_at.push_back(t);
    } else {
      // Under the estimate, each component where it follows it.
      const MountVector estimated = calibration::MountComponents(e.mount);
      for (int i = 0; i < 4; ++i) {
        const bool follows = update->covariance(i, i) > 0.0;
        EXPECT_DOUBLE_EQ(observed_components(i),
                         follows ? estimated(i) : calibration::MountComponents(commissioned)(i))
            << "t " << t << " component " << i;
      }
    }
    suspected = e.step_suspected;
    observed = update->observed;
    if (SameMount(update->mount, bev_mount, 0.0)) continue;
    const MountVector step = Difference(update->mount, bev_mount);
    for (int i = 0; i < 4; ++i)
      EXPECT_LE(std::abs(step(i)), apply.max_step(i) + 1e-12) << "t " << t << " component " << i;
    if (!update_stamps.empty()) {
      EXPECT_GE(t - update_stamps.back(), apply.min_interval_s - 1e-9);
    }
    update_stamps.push_back(t);
    bev_mount = update->mount;
  }
  ASSERT_GE(update_stamps.size(), 10u);  // 1 deg there and back in steps of 0.2 deg at least
  // Both steps were suspected within a window or two (1.5 s each) of happening.
  ASSERT_GE(suspected_at.size(), 2u);
  EXPECT_GT(suspected_at[0], 10.0);
  EXPECT_LT(suspected_at[0], 13.5);
  EXPECT_GE(suspicion_updates, 2);
  ASSERT_TRUE(bev_when_unloaded.has_value());
  const MountVector loaded_off = Difference(*bev_when_unloaded, loaded);
  EXPECT_LT(std::abs(loaded_off(kMountPitch)) * kRadToDeg, 0.05);
  EXPECT_LT(std::abs(loaded_off(kMountRoll)) * kRadToDeg, 0.05);
  EXPECT_LT(std::abs(loaded_off(kMountHeight)) * 1e3, 1.0);
  const MountVector off = Difference(bev_mount, commissioned);
  EXPECT_LT(std::abs(off(kMountPitch)) * kRadToDeg, 0.05);
  EXPECT_LT(std::abs(off(kMountRoll)) * kRadToDeg, 0.05);
  EXPECT_LT(std::abs(off(kMountHeight)) * 1e3, 1.0);
  const MountVector estimate_off = Difference(cal.estimate().mount, commissioned);
  EXPECT_LT(std::abs(estimate_off(kMountPitch)) * kRadToDeg, 0.05);
  EXPECT_LT(std::abs(estimate_off(kMountHeight)) * 1e3, 1.0);
  EXPECT_FALSE(cal.estimate().alarm) << cal.estimate().alarm_message;
  EXPECT_EQ(cal.mount_updates(), updates);
}

// A payload pitches the camera 1 deg and lowers it 1.5 mm. With the wheels'
// scale uncertain (0.2 %: 1.2 mm of height sigma), the height alone would
// never be significantly off its commissioned value; once the step is found,
// every component follows the estimate, which is then nearer the truth than
// the commissioned height. With follow_all_after_step off, the height stays
// commissioned.
TEST(KeyframeMountCalibration, AfterAStepEveryComponentFollowsTheEstimate) {
  const CameraMount commissioned;
  const CameraMount loaded = Moved(commissioned, 1.0, 0.0, -1.5, 0.0);
  calibration::MountSelfCalibrationOptions options;
  options.motion_scale_sigma = 2e-3;
  for (const bool follow_all : {true, false}) {
    SCOPED_TRACE(follow_all ? "follow all after a step" : "significant components only");
    Drive d;
    d.world = Aisle(200.0);
    MountApplyOptions apply;
    apply.follow_all_after_step = follow_all;
    KeyframeMountCalibration cal(commissioned, options, apply);
    CameraMount bev_mount = commissioned;
    std::optional<KeyframeMountCalibration::MountUpdate> last;
    double estimated_mm = 0.0;  // at the last update
    bool height_followed_before_step = false;
    for (double t = 0.0; t < 30.0; t += 1.0 / d.rate_hz) {
      const CameraMount truth = t < 10.0 ? commissioned : loaded;
      cal.AddKeyframe(KeyframeOf(MakeFrame(d, t, truth, bev_mount)));
      if (auto update = cal.DueMountUpdate(t)) {
        if (cal.estimate().steps == 0 && !cal.estimate().step_suspected &&
            update->covariance(kMountHeight, kMountHeight) > 0.0)
          height_followed_before_step = true;
        bev_mount = update->mount;
        last = update;
        estimated_mm = cal.estimate().mount.height_m * 1e3;
      }
    }
    ASSERT_EQ(cal.estimate().steps, 1);
    ASSERT_TRUE(last.has_value());
    EXPECT_FALSE(height_followed_before_step);
    const double observed_mm = last->observed.height_m * 1e3;
    EXPECT_GT(std::sqrt(cal.estimate().covariance(kMountHeight, kMountHeight)) * 1e3, 1.0);
    if (follow_all) {
      EXPECT_DOUBLE_EQ(observed_mm, estimated_mm);
      EXPECT_LT(std::abs(observed_mm - loaded.height_m * 1e3), 0.75);
      EXPECT_GT(last->covariance(kMountHeight, kMountHeight), 0.0);
    } else {
      EXPECT_DOUBLE_EQ(observed_mm, commissioned.height_m * 1e3);
      EXPECT_EQ(last->covariance(kMountHeight, kMountHeight), 0.0);
    }
    EXPECT_LT(std::abs(last->observed.pitch_rad - loaded.pitch_rad) * kRadToDeg, 0.05);
  }
}

// Localized on an atlas, the self-calibration ties markings seen together to
// the atlas's geometry: wheels 0.6 % off put the height from the motion
// about 3.5 mm off, the aisle's lane tapes (1.2 m apart on the atlas) put it
// back near the truth. The keyframes' lines are associated at their pose
// estimates (here the true poses, to the centimetre the association needs).
TEST(KeyframeMountCalibration, OnAnAtlasTheHeightDoesNotFollowTheWheelsScale) {
  Drive d;
  d.world = Aisle(200.0);
  auto atlas = std::make_shared<Atlas>();
  atlas->covariances_stated = true;
  for (std::size_t i = 0; i < d.world.size(); ++i) {
    AtlasLine line;
    line.id = static_cast<std::int64_t>(i);
    line.line_map = perception::LineFromPoints(d.world[i].a, d.world[i].b).value();
    line.endpoint_a_m = d.world[i].a;
    line.endpoint_b_m = d.world[i].b;
    line.covariance =
        LineCovarianceAbout(line.line_map, 0.5 * (d.world[i].a + d.world[i].b), 0.0005, 0.0005);
    atlas->lines.push_back(line);
  }
  ASSERT_TRUE(atlas->Validate().ok()) << atlas->Validate().message();
  const CameraMount commissioned;
  const CameraMount truth = Moved(commissioned, 0.0, 0.0, -4.0, 0.0);
  MountApplyOptions apply;
  apply.enabled = false;  // both see the same frames, under the commissioned mount
  KeyframeMountCalibration wheels(commissioned, calibration::MountSelfCalibrationOptions{}, apply);
  KeyframeMountCalibration on_atlas(commissioned, calibration::MountSelfCalibrationOptions{},
                                    apply);
  on_atlas.SetAtlas(atlas);
  for (double t = 0.0; t < 40.0; t += 1.0 / d.rate_hz) {
    calibration::MountFrame f = MakeFrame(d, t, truth, commissioned);
    f.T_odom_base =
        core::SE2(1.006 * f.T_odom_base.x(), 1.006 * f.T_odom_base.y(), f.T_odom_base.yaw());
    KeyframeOutput k = KeyframeOf(f);
    k.pose.stamp_s = t;
    k.pose.T_map_base = testing_aisle::PoseAt(d, t);
    k.pose.covariance = core::Vector3(1e-6, 1e-6, 1e-7).asDiagonal();
    k.has_covariance = true;
    k.smoother = KeyframeHealth{};
    wheels.AddKeyframe(k);
    on_atlas.AddKeyframe(k);
  }
  const double wheels_off = Difference(wheels.estimate().mount, truth)(kMountHeight) * 1e3;
  const double atlas_off = Difference(on_atlas.estimate().mount, truth)(kMountHeight) * 1e3;
  std::printf("height off after 40 s: wheels %.2f mm, on the atlas %.2f mm\n", wheels_off,
              atlas_off);
  EXPECT_GT(std::abs(wheels_off), 2.0);
  EXPECT_LT(std::abs(atlas_off), 0.5 * std::abs(wheels_off));
  EXPECT_GT(on_atlas.estimate().windows_used, 10);
}

// A component whose sigma stays above max_sigma keeps its value; disabled,
// nothing is applied.
TEST(KeyframeMountCalibration, AComponentTheDriveDoesNotShowIsLeftAlone) {
  const CameraMount commissioned;
  calibration::SavedMountEstimate saved;
  saved.commissioned = commissioned;
  saved.estimate.mount = Moved(commissioned, 0.6, 0.0, -3.0, 1.0);
  saved.estimate.covariance = MountVector(std::pow(0.02 * kDegToRad, 2), std::pow(0.02 * kDegToRad, 2),
                                          std::pow(0.5e-3, 2), std::pow(1.0 * kDegToRad, 2))
                                  .asDiagonal();
  KeyframeMountCalibration cal(commissioned, calibration::MountSelfCalibrationOptions{});
  const auto restored = cal.Restore(saved);
  ASSERT_TRUE(restored.ok()) << restored.message();
  ASSERT_TRUE(restored->has_value());
  // Whole at the start (nothing seen under another mount), yaw left alone.
  const calibration::CameraMount& m = (*restored)->mount;
  EXPECT_NEAR((m.pitch_rad - commissioned.pitch_rad) * kRadToDeg, 0.6, 1e-9);
  EXPECT_NEAR((m.height_m - commissioned.height_m) * 1e3, -3.0, 1e-9);
  EXPECT_EQ(m.yaw_rad, commissioned.yaw_rad);
  EXPECT_EQ((*restored)->covariance(kMountYaw, kMountYaw), 0.0);
  EXPECT_EQ((*restored)->covariance(kMountPitch, kMountYaw), 0.0);
  EXPECT_DOUBLE_EQ((*restored)->covariance(kMountPitch, kMountPitch),
                   saved.estimate.covariance(kMountPitch, kMountPitch));
  // Applied: nothing more is due.
  EXPECT_FALSE(cal.DueMountUpdate(100.0).has_value());

  MountApplyOptions off;
  off.enabled = false;
  KeyframeMountCalibration report_only(commissioned, calibration::MountSelfCalibrationOptions{},
                                       off);
  const auto none = report_only.Restore(saved);
  ASSERT_TRUE(none.ok());
  EXPECT_FALSE(none->has_value());
  EXPECT_FALSE(report_only.DueMountUpdate(100.0).has_value());
  EXPECT_TRUE(SameMount(report_only.applied(), commissioned));

  MountApplyOptions bad;
  bad.max_step(kMountRoll) = 0.0;
  EXPECT_NE(bad.Validate().message().find("max_step"), std::string::npos);
  bad = MountApplyOptions{};
  bad.min_interval_s = std::nan("");
  EXPECT_NE(bad.Validate().message().find("min_interval_s"), std::string::npos);
}

// A floor with a tape running ahead at y = +0.3 m and a bar across at
// x = 1.6 m (both 5 cm wide), photographed by the reference pinhole camera
// on `truth`.
cv::Mat PhotographFloor(const calibration::CameraModel& camera, const Eigen::Matrix3d& K,
                        const CameraMount& truth) {
  // The floor as an image: 2 mm cells over x 0.4..2.8 m, y -1.6..1.6 m
  // (column 0 at y = +1.6, row 0 at x = 2.8).
  const double cell = 0.002, x_max = 2.8, y_max = 1.6;
  cv::Mat floor(static_cast<int>(2.4 / cell), static_cast<int>(3.2 / cell), CV_8UC1);
  cv::RNG rng(11);
  rng.fill(floor, cv::RNG::NORMAL, 110, 5);
  const auto col = [&](double y) { return static_cast<int>((y_max - y) / cell); };
  const auto row = [&](double x) { return static_cast<int>((x_max - x) / cell); };
  cv::rectangle(floor, cv::Point(col(0.325), 0), cv::Point(col(0.275), floor.rows - 1),
                cv::Scalar(225), cv::FILLED);
  cv::rectangle(floor, cv::Point(col(1.0), row(1.625)), cv::Point(col(-1.0), row(1.575)),
                cv::Scalar(225), cv::FILLED);
  // Floor cell (c, r, 1) -> floor point (x, y, 1) -> pixel.
  Eigen::Matrix3d A;
  A << 0.0, -cell, x_max, -cell, 0.0, y_max, 0.0, 0.0, 1.0;
  const Eigen::Matrix3d H =
      calibration::FloorToImageHomography(calibration::BaseFromCamera(truth), K) * A;
  cv::Mat Hcv(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Hcv.at<double>(r, c) = H(r, c);
  cv::Mat image;
  cv::warpPerspective(floor, image, Hcv, cv::Size(camera.width_px(), camera.height_px()),
                      cv::INTER_AREA, cv::BORDER_REPLICATE);
  return image;
}

// The reference pinhole camera, its commissioned mount, a true mount 1 deg
// of pitch and 0.2 deg of roll off it and 5 mm lower, and the floor
// photographed on the truth.
struct PhotographedFloor {
  calibration::CameraModel camera =
      calibration::CameraModel::Pinhole(1132.0, 1132.0, 639.5, 511.5, 1280, 1024);
  CameraMount commissioned;
  CameraMount truth = Moved(CameraMount{}, 1.0, 0.2, -5.0, 0.0);
  cv::Mat image;
};
PhotographedFloor PhotographTheFloor() {
  PhotographedFloor f;
  Eigen::Matrix3d K;
  K << 1132.0, 0.0, 639.5, 0.0, 1132.0, 511.5, 0.0, 0.0, 1.0;
  f.image = PhotographFloor(f.camera, K, f.truth);
  return f;
}

// The lines nearest to the tape (alpha near +90 deg) and the bar (alpha near 0).
struct TapeAndBar {
  const LineObservation* tape = nullptr;
  const LineObservation* bar = nullptr;
};
TapeAndBar Find(const FloorObservations& seen) {
  TapeAndBar found;
  for (const LineObservation& l : seen.lines) {
    const double a = l.line_base.alpha_rad;
    if (std::abs(std::abs(a) - M_PI / 2) < 0.1 && std::abs(l.line_base.rho_m - 0.3) < 0.1)
      found.tape = &l;
    if (std::abs(a) < 0.1 && std::abs(l.line_base.rho_m - 1.6) < 0.2) found.bar = &l;
  }
  return found;
}

// A calibrated odometry's uncertainty replaces the defaults' systematic
// errors: radii known to 0.1 % each, independently, give the default heading
// sigma (the default stands for that) and a mean radius known to 0.1 %
// / sqrt(2); an error common to both wheels scales the motion without
// curving it (scale sigma 0.1 %, heading sigma 0); radii known exactly
// leave neither.
TEST(KeyframeMountCalibration, ACalibratedOdometrySetsTheMotionsSystematicErrors) {
  const calibration::MountSelfCalibrationOptions defaults;
  OdometryCalibration odometry;
  odometry.drive.wheel_radius_m = 0.125;
  const double s = 0.125e-3;  // 0.1 % of the radius
  odometry.drive_covariance = core::Matrix3::Zero();
  odometry.drive_covariance(0, 0) = odometry.drive_covariance(1, 1) = s * s;
  odometry.drive_covariance(2, 2) = 1e-6;  // the track's plays no part
  calibration::MountSelfCalibrationOptions o = WithOdometryCalibration(defaults, odometry);
  EXPECT_NEAR(o.motion_heading_sigma_rad, defaults.motion_heading_sigma_rad, 1e-12);
  EXPECT_NEAR(o.motion_scale_sigma, 1e-3 / std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(o.Validate().ok());

  odometry.drive_covariance(0, 1) = odometry.drive_covariance(1, 0) = s * s;
  o = WithOdometryCalibration(defaults, odometry);
  EXPECT_NEAR(o.motion_scale_sigma, 1e-3, 1e-12);
  EXPECT_NEAR(o.motion_heading_sigma_rad, 0.0, 1e-9);

  odometry.drive_covariance.setZero();
  o = WithOdometryCalibration(defaults, odometry);
  EXPECT_EQ(o.motion_scale_sigma, 0.0);
  EXPECT_EQ(o.motion_heading_sigma_rad, 0.0);
  EXPECT_TRUE(o.Validate().ok());
  // Everything else is kept.
  EXPECT_EQ(o.window_s, defaults.window_s);
  EXPECT_EQ(o.flow_sigma_m, defaults.flow_sigma_m);
}

// What the front end should add to a line's covariance for the mount's
// uncertainty C about `mount`: N J C J^T in the line's description, J the
// derivative of the line through its endpoints by central differences.
Eigen::Matrix2d ExpectedMountCovariance(const LineObservation& line, const CameraMount& mount,
                                        const Eigen::Matrix4d& C) {
  Eigen::Matrix<double, 2, 4> J;
  for (int k = 0; k < 4; ++k) {
    const double h = 1e-5;
    MountVector step = MountVector::Zero();
    step(k) = h;
    const auto moved_line = [&](double sign) {
      const CameraMount m = Moved(mount, sign * step(0) * kRadToDeg, sign * step(1) * kRadToDeg,
                                  sign * step(2) * 1e3, sign * step(3) * kRadToDeg);
      Eigen::Vector2d a, b;
      EXPECT_TRUE(calibration::RemapFloorPoint(line.endpoint_a_base_m, mount, m, &a));
      EXPECT_TRUE(calibration::RemapFloorPoint(line.endpoint_b_base_m, mount, m, &b));
      return perception::LineFromPoints(a, b).value();
    };
    J.col(k) = perception::LineDifference(moved_line(+1), moved_line(-1)) / (2 * h);
  }
  return perception::CovarianceInDescriptionOf(
      perception::LineFromPoints(line.endpoint_a_base_m, line.endpoint_b_base_m).value(),
      line.line_base, FloorFrontEndOptions{}.mount_error_sightings * J * C * J.transpose());
}

TEST(FloorFrontEnd, RebuiltForTheTrueMountReadsTheFloorWhereItIs) {
  const PhotographedFloor photographed = PhotographTheFloor();
  const calibration::CameraModel& camera = photographed.camera;
  const CameraMount& commissioned = photographed.commissioned;
  const CameraMount& truth = photographed.truth;
  const cv::Mat& image = photographed.image;

  core::Result<FloorFrontEnd> as_commissioned = FloorFrontEnd::Create(camera, commissioned);
  ASSERT_TRUE(as_commissioned.ok()) << as_commissioned.message();
  const core::Result<FloorFrontEnd> rebuilt =
      as_commissioned->WithMount(truth, Eigen::Matrix4d::Zero());
  ASSERT_TRUE(rebuilt.ok()) << rebuilt.message();
  EXPECT_TRUE(SameMount(rebuilt->mount(), truth));
  // The BEV keeps its grid.
  EXPECT_EQ(rebuilt->remap().grid().rows(), as_commissioned->remap().grid().rows());
  EXPECT_EQ(rebuilt->remap().grid().cols(), as_commissioned->remap().grid().cols());

  const auto wrong = as_commissioned->Observe(image, 1.0);
  const auto right = rebuilt->Observe(image, 1.0);
  ASSERT_TRUE(wrong.ok() && right.ok());
  ASSERT_TRUE(wrong->observations.camera_mount && right->observations.camera_mount);
  EXPECT_TRUE(SameMount(*wrong->observations.camera_mount, commissioned));
  EXPECT_TRUE(SameMount(*right->observations.camera_mount, truth));
  const TapeAndBar w = Find(wrong->observations), r = Find(right->observations);
  ASSERT_TRUE(w.bar && r.bar && r.tape);
  // Under the commissioned mount the bar is 8-9 cm off (1 deg of pitch at
  // 1.6 m); under the true one within the extraction's millimetres.
  EXPECT_GT(std::abs(w.bar->line_base.rho_m - 1.6), 0.05);
  EXPECT_LT(std::abs(r.bar->line_base.rho_m - 1.6), 0.005);
  EXPECT_LT(std::abs(r.bar->line_base.alpha_rad) * kRadToDeg, 0.3);
  EXPECT_LT(std::abs(r.tape->line_base.rho_m - 0.3), 0.005);
  EXPECT_LT(std::abs(std::abs(r.tape->line_base.alpha_rad) - M_PI / 2) * kRadToDeg, 0.3);

  // The mount's uncertainty is carried into each line: N J C J^T added, J the
  // line through the endpoints moved by the mount (central differences here),
  // N the sightings that share the mount's error.
  Eigen::Matrix4d C = MountVector(std::pow(0.05 * kDegToRad, 2), std::pow(0.05 * kDegToRad, 2),
                                  std::pow(1e-3, 2), std::pow(0.05 * kDegToRad, 2))
                          .asDiagonal();
  const core::Result<FloorFrontEnd> uncertain = as_commissioned->WithMount(truth, C);
  ASSERT_TRUE(uncertain.ok());
  const auto with_c = uncertain->Observe(image, 1.0);
  ASSERT_TRUE(with_c.ok());
  ASSERT_EQ(with_c->observations.lines.size(), right->observations.lines.size());
  for (std::size_t i = 0; i < with_c->observations.lines.size(); ++i) {
    const LineObservation& base = right->observations.lines[i];
    const Eigen::Matrix2d added = with_c->observations.lines[i].covariance - base.covariance;
    const Eigen::Matrix2d expected = ExpectedMountCovariance(base, truth, C);
    EXPECT_NEAR(added(0, 0), expected(0, 0), 1e-3 * expected(0, 0) + 1e-12) << i;
    EXPECT_NEAR(added(1, 1), expected(1, 1), 1e-3 * expected(1, 1) + 1e-12) << i;
    EXPECT_NEAR(added(0, 1), expected(0, 1), 1e-3 * std::abs(expected(0, 1)) + 1e-12) << i;
    EXPECT_GT(added(0, 0), 0.0);
    EXPECT_TRUE(with_c->observations.lines[i].mount_covariance.isApprox(added, 1e-9)) << i;
    EXPECT_TRUE(base.mount_covariance.isZero(0.0)) << i;
  }

  const Eigen::Matrix4d not_psd = -C;
  EXPECT_FALSE(as_commissioned->WithMount(truth, not_psd).ok());
  CameraMount invalid = truth;
  invalid.height_m = -1.0;
  EXPECT_FALSE(as_commissioned->WithMount(invalid, C).ok());
  EXPECT_FALSE(as_commissioned->WithMount(commissioned, C, invalid).ok());
}

// The BEV left on the commissioned mount, its observations expressed under the
// true one: every line's endpoints are where the true mount puts what the BEV
// shows (the remap between the mounts, exactly), the floor is read where it
// is, and the observations say which mount they are under. The mount's
// uncertainty is added about that mount.
TEST(FloorFrontEnd, ExpressesItsObservationsUnderTheObservedMount) {
  const PhotographedFloor photographed = PhotographTheFloor();
  const calibration::CameraModel& camera = photographed.camera;
  const CameraMount& commissioned = photographed.commissioned;
  const CameraMount& truth = photographed.truth;
  const cv::Mat& image = photographed.image;
  const core::Result<FloorFrontEnd> as_commissioned = FloorFrontEnd::Create(camera, commissioned);
  ASSERT_TRUE(as_commissioned.ok()) << as_commissioned.message();
  const core::Result<FloorFrontEnd> observing =
      as_commissioned->WithMount(commissioned, Eigen::Matrix4d::Zero(), truth);
  ASSERT_TRUE(observing.ok()) << observing.message();
  EXPECT_TRUE(SameMount(observing->mount(), commissioned));
  EXPECT_TRUE(SameMount(observing->observed_mount(), truth));
  // The same table: only the observations' mount differs.
  EXPECT_EQ(&observing->remap(), &as_commissioned->remap());

  const auto bev_seen = as_commissioned->Observe(image, 1.0);
  const auto seen = observing->Observe(image, 1.0);
  ASSERT_TRUE(bev_seen.ok() && seen.ok());
  ASSERT_TRUE(seen->observations.camera_mount.has_value());
  EXPECT_TRUE(SameMount(*seen->observations.camera_mount, truth));
  ASSERT_EQ(seen->observations.lines.size(), bev_seen->observations.lines.size());
  for (std::size_t i = 0; i < seen->observations.lines.size(); ++i) {
    const LineObservation& from = bev_seen->observations.lines[i];
    const LineObservation& to = seen->observations.lines[i];
    Eigen::Vector2d a, b;
    ASSERT_TRUE(calibration::RemapFloorPoint(from.endpoint_a_base_m, commissioned, truth, &a));
    ASSERT_TRUE(calibration::RemapFloorPoint(from.endpoint_b_base_m, commissioned, truth, &b));
    EXPECT_LT((to.endpoint_a_base_m - a).norm(), 1e-12) << i;
    EXPECT_LT((to.endpoint_b_base_m - b).norm(), 1e-12) << i;
    EXPECT_NEAR(perception::SignedDistance(to.line_base, a), 0.0, 1e-9) << i;
    EXPECT_NEAR(perception::SignedDistance(to.line_base, b), 0.0, 1e-9) << i;
    EXPECT_NEAR(to.covariance.determinant(), from.covariance.determinant(),
                1e-9 * from.covariance.determinant())
        << i;
  }
  const TapeAndBar w = Find(bev_seen->observations), r = Find(seen->observations);
  ASSERT_TRUE(w.bar && r.bar && r.tape);
  EXPECT_GT(std::abs(w.bar->line_base.rho_m - 1.6), 0.05);
  EXPECT_LT(std::abs(r.bar->line_base.rho_m - 1.6), 0.005);
  EXPECT_LT(std::abs(r.tape->line_base.rho_m - 0.3), 0.005);

  // The uncertainty about the observed mount: what a front end built on it
  // adds to the same endpoints.
  const Eigen::Matrix4d C =
      MountVector(std::pow(0.05 * kDegToRad, 2), 0.0, std::pow(1e-3, 2), 0.0).asDiagonal();
  const core::Result<FloorFrontEnd> uncertain = as_commissioned->WithMount(commissioned, C, truth);
  ASSERT_TRUE(uncertain.ok());
  const auto with_c = uncertain->Observe(image, 1.0);
  ASSERT_TRUE(with_c.ok());
  ASSERT_EQ(with_c->observations.lines.size(), seen->observations.lines.size());
  for (std::size_t i = 0; i < with_c->observations.lines.size(); ++i) {
    const LineObservation& line = with_c->observations.lines[i];
    const Eigen::Matrix2d expected = ExpectedMountCovariance(line, truth, C);
    EXPECT_NEAR(line.mount_covariance(0, 0), expected(0, 0), 1e-3 * expected(0, 0) + 1e-12) << i;
    EXPECT_NEAR(line.mount_covariance(1, 1), expected(1, 1), 1e-3 * expected(1, 1) + 1e-12) << i;
    EXPECT_TRUE((line.covariance - line.mount_covariance)
                    .isApprox(seen->observations.lines[i].covariance, 1e-9))
        << i;
  }
}

}  // namespace
}  // namespace groundline::localization
