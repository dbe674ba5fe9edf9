// Starting without a pose, from a junction recognized on the atlas: the
// Relocalizer on simulated zone drives (observations from the floor map,
// noisy odometry with scale errors). Invariant on every zone and seed: a
// commit is never wrong (within 8 cm of the truth at that keyframe, and the
// heading inside its committed variance; the smoother refines it from there). Zone A's floor is
// distinctive enough to commit without a prior; zone B's repeating aisles are not; with a 2 m prior
// on the start, zones A, B and C commit; a prior far from the true start is reported as
// contradicted by the floor and nothing commits, a right one is not, even where a twin elsewhere
// outscores it for a while.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "floor_localization_run.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/relocalizer.h"
#include "tools_under_test.h"

namespace groundline {
namespace {

struct Outcome {
  bool committed = false;
  double error_m = 0.0;
  double error_deg = 0.0;
  double travel_m = 0.0;  // driven from the start to the commit
  std::size_t seeds = 0;
  // The committed heading's squared error in its own variance, and its sigma.
  double heading_nees = 0.0;
  double sigma_deg = 0.0;
  localization::RelocalizerStatus status;
  Eigen::Vector2d true_start_m = Eigen::Vector2d::Zero();
};

// The observations' errors: those of the floor map's own lines, or coarser
// ones like the lines extracted from rendered images (junctions 4 cm and
// endpoints 2.5 cm 1 sigma, the camera's own +-1 m footprint), which now and
// then leave a frame's marking unmatched at the true pose.
enum class Perception { kFloorMap, kCoarse };

// near_radius_m > 0: a coarse prior of that radius around a point 60 % of
// the radius away from the true start, moved by hint_offset_m (a wrong hint).
Outcome Relocalize(sim::Zone zone, std::uint64_t seed, double duration_s,
                   double near_radius_m = 0.0,
                   const Eigen::Vector2d& hint_offset_m = Eigen::Vector2d::Zero(),
                   Perception perception = Perception::kFloorMap) {
  const testing::ZoneDrive drive = testing::MakeZoneDrive(zone, seed, duration_s);
  const localization::Atlas atlas =
      localization::AtlasFromFloorMap(drive.map, localization::AtlasFromFloorMapOptions());
  localization::RelocalizerOptions options;
  if (near_radius_m > 0.0) {
    options.near_m = drive.trajectory.front().pose.translation() +
                     0.6 * near_radius_m * Eigen::Vector2d(std::sqrt(0.5), std::sqrt(0.5)) +
                     hint_offset_m;
    options.near_radius_m = near_radius_m;
  }
  localization::Relocalizer relocalizer(atlas, options);
  sim::FloorDriveOptions drive_options = testing::TestDriveOptions(seed);
  if (perception == Perception::kCoarse) {
    drive_options.observations.junction_sigma_m = 0.04;
    drive_options.observations.endpoint_sigma_m = 0.025;
    drive_options.observations.half_width_m = 1.0;
  }
  sim::FloorDrive floor_drive(drive.map, drive.trajectory, drive_options);
  sim::DriveKeyframe keyframe;
  Outcome outcome;
  outcome.true_start_m = drive.trajectory.front().pose.translation();
  while (floor_drive.Next(&keyframe)) {
    outcome.travel_m += keyframe.motion.path_length_m;
    const std::optional<localization::PoseEstimate> pose =
        relocalizer.AddFrame(keyframe.stamp_s, keyframe.motion, keyframe.observations);
    if (!pose) continue;
    const double heading_error =
        core::WrapAngle(pose->T_map_base.yaw() - keyframe.T_map_base_true.yaw());
    outcome.heading_nees = heading_error * heading_error / pose->covariance(2, 2);
    outcome.sigma_deg = std::sqrt(pose->covariance(2, 2)) * 180.0 / std::numbers::pi;
    outcome.committed = true;
    outcome.error_m =
        (pose->T_map_base.translation() - keyframe.T_map_base_true.translation()).norm();
    outcome.error_deg =
        std::abs(core::WrapAngle(pose->T_map_base.yaw() - keyframe.T_map_base_true.yaw())) * 180.0 /
        std::numbers::pi;
    break;
  }
  outcome.seeds = relocalizer.status().seeds;
  outcome.status = relocalizer.status();
  return outcome;
}

// A commit is right: within 8 cm of the truth, and its heading within the
// committed variance's 99.9 % bound (chi-square, 1 dof), which the commit
// rule keeps at 0.3 deg (1 sigma) or less.
void ExpectRightPose(const Outcome& o) {
  if (!o.committed) return;
  EXPECT_LT(o.error_m, 0.08);
  EXPECT_LT(o.heading_nees, 10.83);
  EXPECT_LE(
      o.sigma_deg,
      localization::RelocalizerOptions().commit_max_sigma_rad * 180.0 / std::numbers::pi + 1e-9);
}

TEST(Relocalization, DistinctiveFloorCommitsWithoutAPrior) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "thousands of hypotheses over the whole zone take minutes under "
                    "AddressSanitizer; the release build runs this test";
  }
  const Outcome o = Relocalize(sim::Zone::kA, 3, 40.0);
  EXPECT_TRUE(o.committed);
  ExpectRightPose(o);
}

TEST(Relocalization, RepeatingAislesStayAmbiguousWithoutAPrior) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "hundreds of hypotheses over 60 s of driving take minutes under "
                    "AddressSanitizer; the release build runs this test";
  }
  // Zone B's aisle mouths repeat every 4.65 m: the best hypothesis and the
  // one an aisle over explain the floor equally well.
  const Outcome o = Relocalize(sim::Zone::kB, 1, 60.0);
  EXPECT_FALSE(o.committed);
  EXPECT_GE(o.seeds, 1u);
}

class RelocalizationZones : public ::testing::TestWithParam<std::tuple<sim::Zone, std::uint64_t>> {
};

// Zone D's corridor lines lie outside the camera's footprint: it sees
// parallel transverse lines and seldom a junction, so it may not commit;
// nor may zone C, whose crossings repeat every 6 m (seed 3 drives 40 m
// along them after its first line seed and is then past the prior's reach).
TEST_P(RelocalizationZones, WithACoarsePriorCommitsToTheTruePose) {
  const auto [zone, seed] = GetParam();
  if (::groundline::testing::Sanitized()) {
    if (zone != sim::Zone::kB) {
      GTEST_SKIP() << "CI time: zones A, C and D take 30-90 s each under AddressSanitizer (a "
                      "large atlas; C and D never commit); zone B runs here, all four in release";
    }
  }
  const Outcome o = Relocalize(zone, seed, 150.0, 2.0);
  std::printf(
      "zone %d seed %lu, 2 m prior: committed %d after %.1f m, %zu seeds, error %.3f m "
      "%.3f deg; %zu frames contradicted the prior\n",
      static_cast<int>(zone), static_cast<unsigned long>(seed), o.committed, o.travel_m, o.seeds,
      o.error_m, o.error_deg, o.status.frames_hint_contradicted);
  ExpectRightPose(o);
  if (zone == sim::Zone::kA || zone == sim::Zone::kB) {
    EXPECT_TRUE(o.committed);
  }
}

// A hint tens of metres from the true start: the hypotheses it allows
// explain the floor worse than one it excludes (the true pose), so the hint
// is reported as contradicted and nothing commits. The same drives commit
// to the truth with the right hint (WithACoarsePriorCommitsToTheTruePose).
class RelocalizationWrongHint
    : public ::testing::TestWithParam<std::tuple<sim::Zone, std::uint64_t, double, double>> {};

TEST_P(RelocalizationWrongHint, IsReportedAndNothingCommits) {
  const auto [zone, seed, dx_m, dy_m] = GetParam();
  if (::groundline::testing::Sanitized()) {
    if (zone != sim::Zone::kB || seed != 1u) {
      GTEST_SKIP() << "CI time: zone A keeps hundreds of hypotheses the hint excludes, minutes "
                      "under AddressSanitizer, and zone B takes 60-90 s per seed; zone B seed 1 "
                      "runs here, all six in release";
    }
  }
  const Outcome o = Relocalize(zone, seed, 60.0, 2.0, Eigen::Vector2d(dx_m, dy_m));
  const localization::RelocalizerStatus& s = o.status;
  std::printf(
      "zone %d seed %lu, hint moved (%.0f, %.0f) m: committed %d (error %.2f m), %zu seeds, "
      "%zu frames contradicted: allowed %.1f (%d/%d), overall %.1f (%d/%d), %.1f m from the "
      "hint; at the end %zu hypotheses, best %.1f, overall %.1f starting %.1f m from the true "
      "start\n",
      static_cast<int>(zone), static_cast<unsigned long>(seed), dx_m, dy_m, o.committed, o.error_m,
      o.seeds, s.frames_hint_contradicted, s.contradicted_best_log_likelihood,
      s.contradicted_best_matched, s.contradicted_best_matched + s.contradicted_best_unmatched,
      s.contradicted_overall_log_likelihood, s.contradicted_overall_matched,
      s.contradicted_overall_matched + s.contradicted_overall_unmatched,
      s.contradicted_overall_start_from_hint_m, s.hypotheses, s.best_log_likelihood,
      s.overall_log_likelihood, (s.overall_start_m - o.true_start_m).norm());
  EXPECT_FALSE(o.committed);
  EXPECT_GE(o.seeds, 1u);
  EXPECT_TRUE(s.hint_rejected);
  EXPECT_GT(s.frames_hint_contradicted, 0u);
  // The better explanation starts outside the hint's circle.
  EXPECT_GT(s.contradicted_overall_start_from_hint_m, 2.0);
  EXPECT_GE(s.contradicted_overall_log_likelihood - s.contradicted_best_log_likelihood,
            localization::RelocalizerOptions().hint_contradiction_margin);
}

// A right hint (the true start 60 % of its radius from its centre) with the
// coarse perception: a few frames' markings go unmatched at the true pose,
// and among the thousands of hypotheses the hint excludes a twin tens of
// metres away fits them, leading the true pose by 15 or more in
// log-likelihood for some metres of driving, or (zone A seed 7 with a 3.5 m
// hint) for the whole drive. Against the best of thousands that lead is
// luck, not evidence (the look-elsewhere term of the evidence rule): the
// hint is not contradicted, and a commit is right. Seed 6 commits its
// heading 0.8 deg off, within its covariance.
class RelocalizationRightHint
    : public ::testing::TestWithParam<std::tuple<sim::Zone, std::uint64_t, double>> {};

TEST_P(RelocalizationRightHint, IsNotContradictedAndACommitIsRight) {
  const auto [zone, seed, radius_m] = GetParam();
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "CI time: zone A keeps thousands of hypotheses the hint excludes, minutes "
                    "under AddressSanitizer; the release build runs this test";
  }
  const Outcome o =
      Relocalize(zone, seed, 60.0, radius_m, Eigen::Vector2d::Zero(), Perception::kCoarse);
  const localization::RelocalizerStatus& s = o.status;
  std::printf(
      "zone %d seed %lu, right %.1f m hint, coarse perception: committed %d after %.1f m, error "
      "%.3f m %.3f deg (heading NEES %.1f, sigma %.3f deg); %zu frames contradicted the hint "
      "(allowed %.1f, overall %.1f), rejected %d; born %zu allowed, %zu excluded\n",
      static_cast<int>(zone), static_cast<unsigned long>(seed), radius_m, o.committed, o.travel_m,
      o.error_m, o.error_deg, o.heading_nees, o.sigma_deg, s.frames_hint_contradicted,
      s.contradicted_best_log_likelihood, s.contradicted_overall_log_likelihood, s.hint_rejected,
      s.born_allowed, s.born_excluded);
  EXPECT_FALSE(s.hint_rejected);
  EXPECT_TRUE(o.committed);
  ExpectRightPose(o);
}

INSTANTIATE_TEST_SUITE_P(ZoneA, RelocalizationRightHint,
                         ::testing::Values(std::make_tuple(sim::Zone::kA, 1u, 2.0),
                                           std::make_tuple(sim::Zone::kA, 9u, 2.0),
                                           std::make_tuple(sim::Zone::kA, 6u, 3.5),
                                           std::make_tuple(sim::Zone::kA, 7u, 3.5)));

INSTANTIATE_TEST_SUITE_P(Zones, RelocalizationWrongHint,
                         ::testing::Values(std::make_tuple(sim::Zone::kA, 1u, 20.0, 0.0),
                                           std::make_tuple(sim::Zone::kA, 2u, 0.0, -15.0),
                                           std::make_tuple(sim::Zone::kA, 3u, 9.0, -11.0),
                                           std::make_tuple(sim::Zone::kB, 1u, -25.0, 5.0),
                                           std::make_tuple(sim::Zone::kB, 2u, 0.0, 25.0),
                                           std::make_tuple(sim::Zone::kB, 3u, -20.0, -20.0)));

INSTANTIATE_TEST_SUITE_P(AllZones, RelocalizationZones,
                         ::testing::Combine(::testing::Values(sim::Zone::kA, sim::Zone::kB,
                                                              sim::Zone::kC, sim::Zone::kD),
                                            ::testing::Values(1u, 2u, 3u)));

}  // namespace
}  // namespace groundline
