#include "groundline/sim/sim_run.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "groundline/core/dataset.h"
#include "test_data.h"

namespace groundline::sim {
namespace {

SimRunOptions ShortZoneC() {
  SimRunOptions options;
  options.zone = Zone::kC;
  options.route.length_m = 150.0;
  options.seed = 3;
  options.with_camera = false;  // the camera stream has its own test
  return options;
}

TEST(SimRun, WritesAValidDatasetThatReadsBackUnchanged) {
  std::vector<std::string> stages;
  const core::Result<SimRun> run =
      SimulateRun(ShortZoneC(), [&stages](std::string_view stage, double fraction) {
        if (fraction == 0.0) stages.emplace_back(stage);
      });
  ASSERT_TRUE(run.ok()) << run.message();
  EXPECT_EQ(stages, (std::vector<std::string>{"zone", "route", "encoders", "lidar"}));

  const core::Dataset& dataset = run->dataset;
  // One encoder reading per ground-truth step; LiDAR at 15 Hz over the run.
  ASSERT_EQ(dataset.wheel_encoders.size() + 1, dataset.ground_truth.size());
  const double duration_s =
      dataset.ground_truth.back().stamp_s - dataset.ground_truth.front().stamp_s;
  EXPECT_NEAR(static_cast<double>(dataset.scans.size()), duration_s * 15.0, 1.0);
  // Stamped at the middle of the sweep (docs/dataset.md): the TiM571's 270 deg
  // of its 15 Hz mirror turn take 50 ms, the first scan starts with the run.
  ASSERT_FALSE(dataset.scans.empty());
  EXPECT_NEAR(dataset.scans.front().stamp_s - dataset.ground_truth.front().stamp_s,
              0.5 * 818 * 0.33 / 360.0 / 15.0, 1e-9);
  EXPECT_LE(dataset.scans.back().stamp_s, dataset.ground_truth.back().stamp_s);
  ASSERT_TRUE(dataset.manifest.lidar.has_value());
  EXPECT_EQ(dataset.manifest.lidar->stamp, core::LidarStamp::kMidSweep);
  // The start pose a site knows (its dock): the route's first pose.
  ASSERT_TRUE(dataset.manifest.start_pose.has_value());
  EXPECT_EQ(dataset.manifest.start_pose->stamp_s, dataset.ground_truth.front().stamp_s);
  EXPECT_LT((dataset.manifest.start_pose->T_map_base.translation() -
             dataset.ground_truth.front().pose.translation())
                .norm(),
            1e-12);
  // The floor map: the world's markings, then the faces of its installation
  // drawing (wall and rack faces), which zone C's dock walls have.
  ASSERT_TRUE(dataset.floor_map.has_value());
  ASSERT_GT(dataset.floor_map->markings.size(), run->world.markings.size());
  for (std::size_t i = 0; i < dataset.floor_map->markings.size(); ++i) {
    EXPECT_EQ(core::IsFaceKind(dataset.floor_map->markings[i].kind),
              i >= run->world.markings.size())
        << "marking " << i;
  }
  EXPECT_NEAR(run->route.length_m, 150.0, 0.05 * 150.0);

  const auto dir = ::groundline::testing::ScratchDir("sim_run");
  ASSERT_TRUE(core::WriteDataset(dir, dataset).ok());
  const core::Result<core::Dataset> read = core::ReadDataset(dir);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->wheel_encoders.size(), dataset.wheel_encoders.size());
  EXPECT_EQ(read->scans.size(), dataset.scans.size());
  EXPECT_EQ(read->ground_truth.size(), dataset.ground_truth.size());
  EXPECT_EQ(read->manifest.provenance.at("zone"), "C");
  EXPECT_EQ(read->manifest.lidar->stamp, core::LidarStamp::kMidSweep);
  ASSERT_TRUE(read->manifest.start_pose.has_value());
  EXPECT_EQ(read->manifest.start_pose->T_map_base.x(), dataset.manifest.start_pose->T_map_base.x());
  ASSERT_TRUE(read->floor_map.has_value());
  EXPECT_EQ(read->floor_map->markings.size(), dataset.floor_map->markings.size());
  EXPECT_EQ(read->manifest.wheel_encoders->track_m, ShortZoneC().drive.track_m);
}

TEST(SimRun, SameSeedSameRunOtherSeedOtherEncoderNoise) {
  SimRunOptions options = ShortZoneC();
  options.with_lidar = false;
  const core::Result<SimRun> a = SimulateRun(options);
  const core::Result<SimRun> b = SimulateRun(options);
  options.seed = 4;
  const core::Result<SimRun> c = SimulateRun(options);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  ASSERT_EQ(a->dataset.wheel_encoders.size(), b->dataset.wheel_encoders.size());
  for (std::size_t i = 0; i < a->dataset.wheel_encoders.size(); ++i) {
    ASSERT_EQ(a->dataset.wheel_encoders[i].left_delta_rad,
              b->dataset.wheel_encoders[i].left_delta_rad);
  }
  EXPECT_NE(a->encoder_log.left_radius_scale, c->encoder_log.left_radius_scale);
}

TEST(SimRun, DatasetScansUseTheNoReturnSentinel) {
  LaserScan scan;
  scan.range_min_m = 0.05;
  scan.range_max_m = 25.0;
  scan.angle_increment_rad = 0.01;
  scan.ranges_m = {1.5F, std::numeric_limits<float>::infinity(),
                   -std::numeric_limits<float>::infinity()};
  scan.intensities = {0.5F, 0.0F, 0.0F};
  const core::LaserScan out = ToDatasetScan(scan);
  ASSERT_EQ(out.ranges_m.size(), 3u);
  EXPECT_FLOAT_EQ(out.ranges_m[0], 1.5);
  EXPECT_EQ(out.ranges_m[1], core::kNoReturnRange_m);
  EXPECT_EQ(out.ranges_m[2], core::kNoReturnRange_m);
}

TEST(SimRun, InvalidOptionsNameTheField) {
  SimRunOptions options = ShortZoneC();
  options.route.length_m = -5.0;
  const core::Result<SimRun> run = SimulateRun(options);
  ASSERT_FALSE(run.ok());
  EXPECT_NE(run.message().find("length_m"), std::string::npos) << run.message();
}

}  // namespace
}  // namespace groundline::sim
