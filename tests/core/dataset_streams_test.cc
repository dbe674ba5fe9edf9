// The merged sensor streams of a dataset (core/dataset_streams.h), and the
// 1.2 manifest keys the localizer reads (the LiDAR stamp convention, the
// start pose), including the migration of older simulated datasets.
#include "groundline/core/dataset_streams.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <regex>

#include "dataset_fixture.h"
#include "test_data.h"

namespace groundline::core {
namespace {

TEST(DatasetStreams, MergeEveryEventInTimeOrderScansThenFramesThenReadingsAtOneInstant) {
  const auto dir = ::groundline::testing::ScratchDir("dataset_streams");
  Dataset d = ::groundline::testing::MakeSyntheticDataset(dir);
  // A frame and a scan at exactly a reading's instant.
  d.images.push_back({d.wheel_encoders[60].stamp_s, "000099.png"});
  ::groundline::testing::WriteText(dir / "images" / "000099.png", "fixture\n");
  LaserScan scan = d.scans.back();
  scan.stamp_s = d.wheel_encoders[60].stamp_s;
  d.scans.push_back(scan);
  std::sort(d.images.begin(), d.images.end(),
            [](const ImageRecord& a, const ImageRecord& b) { return a.stamp_s < b.stamp_s; });
  d.UseDefaultFileNames();
  ASSERT_TRUE(WriteDataset(dir, d).ok());
  DatasetReadOptions read;
  read.load_scans = false;
  Result<Dataset> loaded = ReadDataset(dir, read);
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  Result<DatasetStreams> streams = DatasetStreams::Open(dir, *loaded);
  ASSERT_TRUE(streams.ok()) << streams.message();
  DatasetEvent event;
  std::vector<DatasetEvent> events;
  while (true) {
    Result<bool> next = streams->Next(&event);
    ASSERT_TRUE(next.ok()) << next.message();
    if (!*next) break;
    events.push_back(event);
  }
  ASSERT_EQ(events.size(), d.wheel_encoders.size() + d.images.size() + d.scans.size());
  for (std::size_t i = 1; i < events.size(); ++i) {
    ASSERT_LE(events[i - 1].stamp_s, events[i].stamp_s + 1e-9) << i;
  }
  const double at_s = d.wheel_encoders[60].stamp_s;
  std::vector<DatasetEvent::Kind> at;
  for (const DatasetEvent& e : events) {
    if (std::abs(e.stamp_s - at_s) < 1e-9) at.push_back(e.kind);
  }
  EXPECT_EQ(at,
            (std::vector<DatasetEvent::Kind>{DatasetEvent::Kind::kScan, DatasetEvent::Kind::kFrame,
                                             DatasetEvent::Kind::kWheel}));
  // Frames carry their file; scans their ranges.
  for (const DatasetEvent& e : events) {
    if (e.kind == DatasetEvent::Kind::kFrame) {
      EXPECT_TRUE(std::filesystem::exists(e.image_path));
    }
    if (e.kind == DatasetEvent::Kind::kScan) {
      EXPECT_EQ(e.scan.ranges_m.size(), 181u);
    }
  }
}

TEST(DatasetManifest, TheLidarStampAndTheStartPoseRoundTrip) {
  const auto dir = ::groundline::testing::ScratchDir("manifest_12");
  Dataset d = ::groundline::testing::MakeSyntheticDataset(dir);
  d.manifest.lidar->stamp = LidarStamp::kFirstRay;
  d.manifest.start_pose =
      StartPose{d.ground_truth.front().stamp_s, SE2(1.5, -2.0, 0.3), 0.01, 0.002};
  d.UseDefaultFileNames();
  ASSERT_TRUE(WriteDataset(dir, d).ok());
  Result<DatasetManifest> read = ReadDatasetManifest(dir / "manifest.yaml");
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->lidar->stamp, LidarStamp::kFirstRay);
  ASSERT_TRUE(read->start_pose.has_value());
  EXPECT_EQ(read->start_pose->T_map_base.y(), -2.0);
  EXPECT_EQ(read->start_pose->sigma_xy_m, 0.01);

  // A bad convention is refused with its key and line.
  std::string text = ::groundline::testing::ReadText(dir / "manifest.yaml");
  const std::string bad =
      std::regex_replace(text, std::regex("stamp: \"first_ray\""), "stamp: \"end\"");
  ::groundline::testing::WriteText(dir / "manifest.yaml", bad);
  Result<DatasetManifest> refused = ReadDatasetManifest(dir / "manifest.yaml");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("sensors.lidar.stamp"), std::string::npos) << refused.message();

  // A 1.1 manifest from the simulator before its provenance said mid_sweep:
  // its scans are stamped at the first ray.
  std::string old = std::regex_replace(text, std::regex("version: 1.2"), "version: 1.1");
  old = std::regex_replace(old, std::regex("    stamp: \"first_ray\"\n"), "");
  old = std::regex_replace(old, std::regex("start_pose: .*\n"), "");
  old = std::regex_replace(old, std::regex("\"generator\": \"[^\"]*\""),
                           "\"generator\": \"groundline sim\"");
  ::groundline::testing::WriteText(dir / "manifest.yaml", old);
  Result<DatasetManifest> migrated = ReadDatasetManifest(dir / "manifest.yaml");
  ASSERT_TRUE(migrated.ok()) << migrated.message();
  EXPECT_EQ(migrated->lidar->stamp, LidarStamp::kFirstRay);
  EXPECT_FALSE(migrated->start_pose.has_value());
  ::groundline::testing::WriteText(
      dir / "manifest.yaml", std::regex_replace(old, std::regex("provenance:\n"),
                                                "provenance:\n  \"lidar_stamp\": \"mid_sweep\"\n"));
  Result<DatasetManifest> mid = ReadDatasetManifest(dir / "manifest.yaml");
  ASSERT_TRUE(mid.ok()) << mid.message();
  EXPECT_EQ(mid->lidar->stamp, LidarStamp::kMidSweep);
}

}  // namespace
}  // namespace groundline::core
