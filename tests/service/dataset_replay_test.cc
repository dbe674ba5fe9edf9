// The dataset replay through the causal localizer (service/replay.h,
// service/dataset_localizer.h) on a short simulated zone B drive: the same
// estimate whether or not the manifest says it comes from the simulator,
// and the wall lines the floor map carries make the LiDAR beat the odometry.
#include "groundline/service/replay.h"

#include <gtest/gtest.h>

#include "groundline/core/dataset.h"
#include "groundline/core/dataset_streams.h"
#include "groundline/core/trajectory_metrics.h"
#include "groundline/service/dataset_localizer.h"
#include "groundline/sim/sim_run.h"
#include "simulated_drive.h"
#include "test_data.h"
#include "tools_under_test.h"

namespace groundline::service {
namespace {

namespace loc = localization;

struct LocalizedRun {
  core::Trajectory keyframes;
  loc::LocalizerCounters counters;
};

LocalizedRun Localize(const std::filesystem::path& dir, const loc::LocalizerOptions& options) {
  core::DatasetReadOptions read;
  read.load_scans = false;
  read.check_image_files = false;
  core::Result<core::Dataset> dataset = core::ReadDataset(dir, read);
  EXPECT_TRUE(dataset.ok()) << dataset.message();
  DatasetLocalizerOptions setup_options;
  setup_options.localizer = options;
  core::Result<DatasetSetup> setup = SetupFromDataset(dir, *dataset, setup_options);
  EXPECT_TRUE(setup.ok()) << setup.message();
  EXPECT_TRUE(setup->start_pose.has_value());
  auto localizer = std::move(loc::Localizer::Create(options, std::move(setup->setup))).value();
  EXPECT_TRUE(localizer
                  ->SetInitialPose(setup->start_pose->stamp_s, setup->start_pose->T_map_base,
                                   StartCovariance(*setup->start_pose))
                  .ok());
  core::Result<core::DatasetStreams> streams = core::DatasetStreams::Open(dir, *dataset);
  EXPECT_TRUE(streams.ok()) << streams.message();
  LocalizedRun run;
  ReplayCallbacks callbacks;
  callbacks.on_keyframe = [&run](const loc::KeyframeOutput& k) {
    run.keyframes.push_back({k.stamp_s, k.pose.T_map_base, std::nullopt});
  };
  EXPECT_TRUE(Replay(*streams, *localizer, ReplayOptions(), callbacks).ok());
  run.counters = localizer->counters();
  return run;
}

double AteRmse(const LocalizedRun& run, const core::Trajectory& truth) {
  core::Result<core::TrajectoryErrorSummary> errors =
      core::ComputeTrajectoryErrors(run.keyframes, truth);
  EXPECT_TRUE(errors.ok()) << errors.message();
  return errors->ate_m.rmse;
}

TEST(DatasetReplay, TheSameEstimateWithoutTheSimulatorsProvenanceAndWallsBeatOdometry) {
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP()
        << "minutes of Debug scan matching under AddressSanitizer; runs in the release build";
  }
  const auto scratch = ::groundline::testing::ScratchDir("dataset_replay");
  const auto from_sim = scratch / "from_sim", from_site = scratch / "from_site";
  const std::optional<sim::SimRun> simulated = testing::SimulatedZoneBDrive(25.0, 5, from_sim);
  ASSERT_TRUE(simulated.has_value());
  core::Dataset site = simulated->dataset;  // a site's copy: nobody says where it came from
  site.manifest.provenance.clear();
  site.manifest.name = "site_drive";
  ASSERT_TRUE(core::WriteDataset(from_site, site).ok());

  const loc::LocalizerOptions fusion = loc::LocalizerOptions::ForFusion();
  const LocalizedRun a = Localize(from_sim, fusion);
  const LocalizedRun b = Localize(from_site, fusion);
  ASSERT_GT(a.keyframes.size(), 50u);
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (std::size_t i = 0; i < a.keyframes.size(); ++i) {
    ASSERT_EQ(a.keyframes[i].stamp_s, b.keyframes[i].stamp_s);
    ASSERT_EQ(a.keyframes[i].pose.x(), b.keyframes[i].pose.x()) << i;
    ASSERT_EQ(a.keyframes[i].pose.yaw(), b.keyframes[i].pose.yaw()) << i;
  }
  // The rack faces of the floor map are seen and used.
  EXPECT_GT(a.counters.walls_used, 100);
  EXPECT_GT(a.counters.scans_matched, 200);

  loc::LocalizerOptions odometry;
  odometry.mode = loc::LocalizerMode::kOdometry;
  const LocalizedRun dead_reckoning = Localize(from_site, odometry);
  const double ate_fusion = AteRmse(b, simulated->dataset.ground_truth);
  const double ate_odometry = AteRmse(dead_reckoning, simulated->dataset.ground_truth);
  EXPECT_LT(ate_fusion, 0.02);
  EXPECT_LT(ate_fusion, ate_odometry);
}

}  // namespace
}  // namespace groundline::service
