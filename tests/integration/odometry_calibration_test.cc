// Odometry calibration from a localized drive (odometry_calibration.h): a
// simulated vehicle whose wheel radii, track and wheel noise differ from the
// nominal geometry and the default noise drives a zone route; the localizer
// (floor lines simulated from the floor map at the true poses, with their
// stated noise) localizes it on the surveyed atlas with the nominal
// geometry, and the calibration recovers the true geometry and noise from
// that estimate. Dead reckoning with the calibration is then checked
// against the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "groundline/core/angles.h"
#include "groundline/core/trajectory_metrics.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/localizer.h"
#include "groundline/localization/odometry_calibration.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/sim/floor_line_observations.h"
#include "groundline/sim/route.h"
#include "groundline/sim/sim_run.h"
#include "groundline/sim/wheel_encoders.h"
#include "groundline/sim/zones.h"
#include "tools_under_test.h"

namespace groundline::localization {
namespace {

constexpr double kNominalRadiusM = 0.125;
constexpr double kNominalTrackM = 0.760;

struct Drive {
  core::FloorMap map;
  core::Trajectory truth;  // at the encoder rate
  std::vector<core::WheelEncoderReading> readings;
  sim::WheelEncoderLog log;
};

DiffDriveParams Nominal() {
  DiffDriveParams d;
  d.wheel_radius_m = kNominalRadiusM;
  d.track_m = kNominalTrackM;
  return d;
}

// The simulated vehicle's true geometry (the encoder log's scales).
DiffDriveParams TrueGeometry(const Drive& d) {
  DiffDriveParams g = Nominal();
  g.left_wheel_radius_m = kNominalRadiusM * d.log.left_radius_scale;
  g.right_wheel_radius_m = kNominalRadiusM * d.log.right_radius_scale;
  g.track_m = kNominalTrackM * d.log.track_scale;
  return g;
}

// Each of the calibrated radii and track within 3 sigma of the truth, sigma
// as the calibration states it.
void ExpectGeometryWithinThreeSigma(const OdometryCalibration& c, const DiffDriveParams& truth) {
  const core::Vector3 sigma = c.drive_covariance.diagonal().cwiseSqrt();
  EXPECT_LT(std::abs(c.drive.LeftRadius() - truth.LeftRadius()), 3.0 * sigma(0));
  EXPECT_LT(std::abs(c.drive.RightRadius() - truth.RightRadius()), 3.0 * sigma(1));
  EXPECT_LT(std::abs(c.drive.track_m - truth.track_m), 3.0 * sigma(2));
}

// A closed zone B loop of about 600 m at 100 Hz, and the encoders of a vehicle
// whose left wheel is 0.3 % larger and right wheel 0.2 % smaller than
// nominal, with a 1 % wider effective track and three times the default
// wheel noise; slips as the standard scenarios have them.
Drive MakeDrive(std::uint64_t seed, double slip_rate_per_m, double length_m = 600.0) {
  Drive d;
  const sim::World world = sim::BuildZone(sim::Zone::kB, seed).value();
  sim::RouteOptions route_options;
  route_options.seed = seed;
  route_options.length_m = length_m;
  route_options.closed_loop = true;
  route_options.length_tolerance_fraction = 0.5;
  route_options.sample_rate_hz = 100.0;
  const core::Result<sim::Route> route = sim::GenerateRoute(world, route_options);
  EXPECT_TRUE(route.ok()) << route.message();
  if (!route.ok()) return d;
  d.map = sim::ToFloorMap(world);
  d.truth = route->T_map_base;
  sim::WheelEncoderOptions encoders;
  encoders.seed = seed;
  encoders.max_lateral_step_m = 1e-5;
  encoders.left_radius_scale = 1.003;
  encoders.right_radius_scale = 0.998;
  encoders.track_scale = 1.01;
  encoders.wheel_variance_m2_per_m = 3e-5;
  encoders.slip_rate_per_m = slip_rate_per_m;
  core::Result<sim::WheelEncoderLog> log = sim::SimulateWheelEncoders(d.truth, Nominal(), encoders);
  EXPECT_TRUE(log.ok()) << log.message();
  if (!log.ok()) return d;
  d.log = std::move(log).value();
  for (const sim::EncoderReading& r : d.log.readings) {
    d.readings.push_back({r.stamp_s, r.increment.left_rad, r.increment.right_rad});
  }
  return d;
}

// The drive localized on the floor map's atlas with the nominal geometry and
// the default noise (LocalizerOptions::ForFusion without the LiDAR): frames at
// 10 Hz observed from the true pose.
core::Trajectory Localize(const Drive& d, const DiffDriveParams& drive) {
  LocalizerOptions options = LocalizerOptions::ForFusion();
  options.use_lidar = false;
  LocalizerSetup setup;
  setup.drive = drive;
  setup.atlas = AtlasFromFloorMap(d.map, AtlasFromFloorMapOptions());
  core::Result<std::unique_ptr<Localizer>> made = Localizer::Create(options, setup);
  EXPECT_TRUE(made.ok()) << made.message();
  if (!made.ok()) return {};
  Localizer& localizer = **made;
  EXPECT_TRUE(localizer
                  .SetInitialPose(d.truth.front().stamp_s, d.truth.front().pose,
                                  core::Vector3(1e-6, 1e-6, 1e-7).asDiagonal())
                  .ok());
  sim::FloorObservationOptions view;
  view.half_width_m = 1.25;  // the aisle tapes 1.03 m from the aisle's centre
  view.seed = 3;
  sim::FloorObservationSimulator observer(d.map, view);
  core::Trajectory keyframes;
  double next_frame_s = d.truth.front().stamp_s + 0.1;
  for (std::size_t k = 0; k < d.readings.size(); ++k) {
    const core::StampedPose& at = d.truth[k + 1];  // reading k ends at truth pose k + 1
    if (at.stamp_s >= next_frame_s) {
      ConvertedObservations seen;
      seen.observations = observer.Observe(at.stamp_s, at.pose);
      localizer.AddFloorObservations(seen);
      next_frame_s += 0.1;
    }
    if (auto out = localizer.AddWheelReading(d.readings[k])) {
      if (out->has_covariance) {
        keyframes.push_back({out->pose.stamp_s, out->pose.T_map_base, out->pose.covariance});
      }
    }
  }
  return keyframes;
}

// Dead reckoning over the whole drive with `drive`: the RMS position error
// against the truth.
double DeadReckoningRms(const Drive& d, const DiffDriveParams& drive) {
  OdometryIntegrator integrator(drive, OdometryNoiseParams{});
  integrator.Reset(d.truth.front().pose);
  double sum = 0.0;
  for (std::size_t k = 0; k < d.readings.size(); ++k) {
    integrator.Integrate(
        WheelAngleIncrement{d.readings[k].left_delta_rad, d.readings[k].right_delta_rad});
    sum +=
        (integrator.T_odom_base().translation() - d.truth[k + 1].pose.translation()).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(d.readings.size()));
}

TEST(OdometryCalibration, ALocalizedDriveRecoversTheRadiiTheTrackAndTheWheelNoise) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "a 600 m localized drive: 90 s under AddressSanitizer (Debug); the estimator "
                    "itself runs under it in AgainstTheTrueTrajectoryTheEstimateIsConsistent";
  }
  const Drive d = MakeDrive(21, 2e-3);
  ASSERT_FALSE(d.readings.empty());
  const core::Trajectory localized = Localize(d, Nominal());
  ASSERT_GT(localized.size(), 500u);
  OdometryCalibrationOptions options;
  const core::Result<OdometryCalibration> c =
      CalibrateOdometry(d.readings, Nominal(), localized, options);
  ASSERT_TRUE(c.ok()) << c.message();
  const DiffDriveParams truth = TrueGeometry(d);
  const double true_left = truth.LeftRadius(), true_right = truth.RightRadius();
  const double true_track = truth.track_m;
  const core::Vector3 sigma = c->drive_covariance.diagonal().cwiseSqrt();
  std::printf(
      "%d segments (%d rejected, %zu slips), %.0f m, %.0f deg; left %.6f (true %.6f, sigma "
      "%.2g), right %.6f (true %.6f, sigma %.2g), track %.5f (true %.5f, sigma %.2g) m; wheel "
      "variance %.3g (sigma %.2g, true %.3g), lateral %.3g m^2/m; mean chi2/3 %.2f\n",
      c->segments, c->segments_rejected, d.log.slips.size(), c->distance_m,
      c->rotation_rad * core::kRadToDeg, c->drive.LeftRadius(), true_left, sigma(0),
      c->drive.RightRadius(), true_right, sigma(1), c->drive.track_m, true_track, sigma(2),
      c->wheel_variance_m2_per_m, c->wheel_variance_sigma_m2_per_m, 3e-5,
      c->lateral_variance_m2_per_m, c->mean_normalized_chi2);
  // The radii to 0.1 % (their 0.2-0.3 % errors found), the track to 0.5 %
  // (its 1 %), each within 3 sigma of what the fit states.
  EXPECT_NEAR(c->drive.LeftRadius(), true_left, 1e-3 * kNominalRadiusM);
  EXPECT_NEAR(c->drive.RightRadius(), true_right, 1e-3 * kNominalRadiusM);
  EXPECT_NEAR(c->drive.track_m, true_track, 5e-3 * kNominalTrackM);
  ExpectGeometryWithinThreeSigma(*c, truth);
  // The noise: three times the default the localizer assumed, found within a
  // factor 1.5.
  EXPECT_GT(c->wheel_variance_m2_per_m, 3e-5 / 1.5);
  EXPECT_LT(c->wheel_variance_m2_per_m, 3e-5 * 1.5);
  EXPECT_GT(c->segments, 200);
  // The keyframes' covariances taken as independent overstate the estimate's
  // share of the residuals: below 1, not far below.
  EXPECT_GT(c->mean_normalized_chi2, 0.3);
  EXPECT_LT(c->mean_normalized_chi2, 1.3);
  // Dead reckoning with the calibrated geometry against the nominal.
  const double nominal_rms = DeadReckoningRms(d, Nominal());
  const double calibrated_rms = DeadReckoningRms(d, c->drive);
  std::printf("dead reckoning RMS: nominal %.3f m, calibrated %.3f m\n", nominal_rms,
              calibrated_rms);
  EXPECT_LT(calibrated_rms, 0.1 * nominal_rms);
}

// The estimator alone: against the true trajectory (every 0.25 m, stated
// with 1 mm and 0.006 deg), the geometry is found within its stated 3 sigma
// and the wheel noise within 20 %.
TEST(OdometryCalibration, AgainstTheTrueTrajectoryTheEstimateIsConsistent) {
  // Sanitized, the same checks on half the drive: minutes instrumented.
  const double loop_m = ::groundline::testing::Sanitized() ? 300.0 : 600.0;
  const Drive d = MakeDrive(22, 0.0, loop_m);
  ASSERT_FALSE(d.readings.empty());
  core::Trajectory poses;
  double last_x = 1e9, last_y = 1e9;
  for (const core::StampedPose& p : d.truth) {
    if (std::hypot(p.pose.x() - last_x, p.pose.y() - last_y) < 0.25) continue;
    last_x = p.pose.x();
    last_y = p.pose.y();
    poses.push_back(
        {p.stamp_s, p.pose, core::Matrix3(core::Vector3(1e-6, 1e-6, 1e-8).asDiagonal())});
  }
  const core::Result<OdometryCalibration> c = CalibrateOdometry(d.readings, Nominal(), poses);
  ASSERT_TRUE(c.ok()) << c.message();
  const DiffDriveParams truth = TrueGeometry(d);
  const double true_left = truth.LeftRadius(), true_right = truth.RightRadius();
  const double true_track = truth.track_m;
  const core::Vector3 sigma = c->drive_covariance.diagonal().cwiseSqrt();
  std::printf(
      "truth: %d segments; left %+.1f um (sigma %.1f), right %+.1f um (sigma %.1f), track %+.2f "
      "mm (sigma %.2f); wheel variance %.3g (true 3e-5), lateral %.3g; mean chi2/3 %.2f\n",
      c->segments, 1e6 * (c->drive.LeftRadius() - true_left), 1e6 * sigma(0),
      1e6 * (c->drive.RightRadius() - true_right), 1e6 * sigma(1),
      1e3 * (c->drive.track_m - true_track), 1e3 * sigma(2), c->wheel_variance_m2_per_m,
      c->lateral_variance_m2_per_m, c->mean_normalized_chi2);
  ExpectGeometryWithinThreeSigma(*c, truth);
  EXPECT_GT(c->wheel_variance_m2_per_m, 3e-5 / 1.5);
  EXPECT_LT(c->wheel_variance_m2_per_m, 3e-5 * 1.5);
  EXPECT_NEAR(c->mean_normalized_chi2, 1.0, 0.3);
}

TEST(OdometryCalibration, TheFileRoundTripsAndBadFilesNameTheField) {
  OdometryCalibration c;
  c.drive = Nominal();
  c.drive.left_wheel_radius_m = 0.1254;
  c.drive.right_wheel_radius_m = 0.1247;
  c.drive.track_m = 0.768;
  c.drive_covariance = core::Vector3(1e-10, 2e-10, 3e-8).asDiagonal();
  c.wheel_variance_m2_per_m = 3.1e-5;
  c.lateral_variance_m2_per_m = 2e-8;
  c.segments = 90;
  c.source = "drive_a";
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir());
  const std::filesystem::path path = dir / "odometry_calibration.json";
  ASSERT_TRUE(WriteOdometryCalibration(path, c).ok());
  const core::Result<OdometryCalibration> read = ReadOdometryCalibration(path);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_DOUBLE_EQ(read->drive.LeftRadius(), 0.1254);
  EXPECT_DOUBLE_EQ(read->drive.RightRadius(), 0.1247);
  EXPECT_DOUBLE_EQ(read->drive.track_m, 0.768);
  EXPECT_DOUBLE_EQ(read->drive.wheel_radius_m, kNominalRadiusM);
  EXPECT_DOUBLE_EQ(read->drive_covariance(2, 2), 3e-8);
  EXPECT_DOUBLE_EQ(read->wheel_variance_m2_per_m, 3.1e-5);
  EXPECT_DOUBLE_EQ(read->lateral_variance_m2_per_m, 2e-8);
  EXPECT_EQ(read->segments, 90);
  EXPECT_EQ(read->source, "drive_a");

  const auto write = [&](const std::string& text) {
    std::ofstream(dir / "bad_odometry.json") << text;
    return ReadOdometryCalibration(dir / "bad_odometry.json");
  };
  auto bad = write(
      "{\"format\": \"groundline-odometry-calibration\", \"left_wheel_radius_m\": "
      "0.125, \"right_wheel_radius_m\": -1, \"track_m\": 0.76, "
      "\"wheel_variance_m2_per_m\": 1e-5, \"lateral_variance_m2_per_m\": 1e-7}");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("right_wheel_radius_m"), std::string::npos) << bad.message();
  EXPECT_NE(bad.message().find("bad_odometry.json"), std::string::npos) << bad.message();
  bad = write("{\"format\": \"groundline-odometry-calibration\", \"left_wheel_radius_m\": 0.125}");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("right_wheel_radius_m' is missing"), std::string::npos)
      << bad.message();
  bad = write("{\"format\": \"an atlas\"}");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("format"), std::string::npos) << bad.message();
  bad = write("not json");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("not JSON"), std::string::npos) << bad.message();
}

TEST(OdometryCalibration, ADriveThatNeverTurnsOrIsNotLocalizedIsRefusedWithTheReason) {
  // 60 m straight at 1 m/s, localized perfectly: the track is not observable.
  std::vector<core::WheelEncoderReading> readings;
  core::Trajectory localized;
  const double delta_rad = 0.01 / kNominalRadiusM;
  for (int k = 1; k <= 6000; ++k) readings.push_back({0.01 * k, delta_rad, delta_rad});
  for (int k = 0; k <= 600; ++k) {
    localized.push_back({0.1 * k, core::SE2(0.1 * k, 0.0, 0.0),
                         core::Matrix3(core::Vector3(1e-6, 1e-6, 1e-7).asDiagonal())});
  }
  core::Result<OdometryCalibration> c = CalibrateOdometry(readings, Nominal(), localized);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.message().find("turns"), std::string::npos) << c.message();
  // The same poses without covariances: nothing localized.
  for (core::StampedPose& p : localized) p.covariance.reset();
  c = CalibrateOdometry(readings, Nominal(), localized);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.message().find("localized"), std::string::npos) << c.message();
  OdometryCalibrationOptions options;
  options.min_segment_m = 0.0;
  c = CalibrateOdometry(readings, Nominal(), localized, options);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.message().find("min_segment_m"), std::string::npos) << c.message();
}

}  // namespace
}  // namespace groundline::localization
