#include "groundline/core/dataset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "dataset_fixture.h"
#include "groundline/core/dataset_summary.h"
#include "test_data.h"

namespace groundline::core {
namespace {

using ::groundline::testing::LineContaining;
using ::groundline::testing::MakeSyntheticDataset;
using ::groundline::testing::ReadText;
using ::groundline::testing::ReplaceInFile;
using ::groundline::testing::ScratchDir;

// Written precision: stamps and wheel deltas 9 decimals (error <= 5e-10),
// ranges 4 decimals (<= 5e-5), intensities 6 significant digits (relative
// <= 5e-6); scan angles, YAML numbers and the floor map are exact (shortest
// round trip).
constexpr double kStampTol_s = 5e-10 + 1e-12;
constexpr double kAngleTol_rad = 5e-10 + 1e-12;
constexpr double kRangeTol_m = 5e-5 + 1e-12;

void ExpectSameManifest(const DatasetManifest& a, const DatasetManifest& b) {
  EXPECT_EQ(b.version_major, kDatasetFormatMajor);
  EXPECT_EQ(b.version_minor, kDatasetFormatMinor);
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.description, b.description);
  EXPECT_EQ(a.frames.map, b.frames.map);
  EXPECT_EQ(a.frames.odom, b.frames.odom);
  EXPECT_EQ(a.frames.base_link, b.frames.base_link);
  ASSERT_TRUE(b.camera && b.wheel_encoders && b.lidar);
  EXPECT_EQ(a.camera->image_width_px, b.camera->image_width_px);
  EXPECT_EQ(a.camera->image_height_px, b.camera->image_height_px);
  EXPECT_EQ(a.camera->rate_hz, b.camera->rate_hz);
  EXPECT_EQ(a.camera->intrinsics_file, b.camera->intrinsics_file);
  EXPECT_EQ(a.camera->extrinsics_file, b.camera->extrinsics_file);
  EXPECT_EQ(a.wheel_encoders->rate_hz, b.wheel_encoders->rate_hz);
  EXPECT_EQ(a.wheel_encoders->wheel_radius_m, b.wheel_encoders->wheel_radius_m);
  EXPECT_EQ(a.wheel_encoders->track_m, b.wheel_encoders->track_m);
  EXPECT_EQ(a.wheel_encoders->ticks_per_rev, b.wheel_encoders->ticks_per_rev);
  EXPECT_EQ(a.lidar->rate_hz, b.lidar->rate_hz);
  EXPECT_EQ(a.lidar->T_base_lidar.Vector(), b.lidar->T_base_lidar.Vector());
  EXPECT_EQ(a.lidar->mount_height_m, b.lidar->mount_height_m);
  EXPECT_EQ(a.lidar->range_min_m, b.lidar->range_min_m);
  EXPECT_EQ(a.lidar->range_max_m, b.lidar->range_max_m);
  EXPECT_EQ(a.files.image_index, b.files.image_index);
  EXPECT_EQ(a.files.wheel_encoders, b.files.wheel_encoders);
  EXPECT_EQ(a.files.lidar_scans, b.files.lidar_scans);
  EXPECT_EQ(a.files.ground_truth, b.files.ground_truth);
  EXPECT_EQ(a.files.floor_map, b.files.floor_map);
  EXPECT_EQ(a.provenance, b.provenance);
}

void ExpectSameScans(const std::vector<LaserScan>& a, const std::vector<LaserScan>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t s = 0; s < a.size(); ++s) {
    SCOPED_TRACE("scan " + std::to_string(s));
    EXPECT_NEAR(a[s].stamp_s, b[s].stamp_s, kStampTol_s);
    EXPECT_EQ(a[s].angle_min_rad, b[s].angle_min_rad);
    EXPECT_EQ(a[s].angle_increment_rad, b[s].angle_increment_rad);
    EXPECT_NEAR(a[s].range_min_m, b[s].range_min_m, kRangeTol_m);
    EXPECT_NEAR(a[s].range_max_m, b[s].range_max_m, kRangeTol_m);
    ASSERT_EQ(a[s].ranges_m.size(), b[s].ranges_m.size());
    ASSERT_EQ(a[s].intensities.size(), b[s].intensities.size());
    for (std::size_t i = 0; i < a[s].ranges_m.size(); ++i) {
      EXPECT_NEAR(a[s].ranges_m[i], b[s].ranges_m[i], kRangeTol_m) << "beam " << i;
      EXPECT_EQ(a[s].IsReturn(i), b[s].IsReturn(i)) << "beam " << i;
    }
    for (std::size_t i = 0; i < a[s].intensities.size(); ++i) {
      EXPECT_NEAR(a[s].intensities[i], b[s].intensities[i], 5e-6 * a[s].intensities[i] + 1e-12);
    }
  }
}

TEST(Dataset, RoundTripsEveryFieldWithinTheWrittenPrecision) {
  const std::filesystem::path dir = ScratchDir("round_trip");
  const Dataset written = MakeSyntheticDataset(dir);
  const Status status = WriteDataset(dir, written);
  ASSERT_TRUE(status.ok()) << status.message();
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_TRUE(read.ok()) << read.message();
  const Dataset& d = *read;

  ExpectSameManifest(written.manifest, d.manifest);
  // Stamps near 1.7e9 s: a double resolves 2.4e-7 s there, so the 9 written
  // decimals reproduce the double exactly.
  ASSERT_EQ(written.images.size(), d.images.size());
  for (std::size_t i = 0; i < d.images.size(); ++i) {
    EXPECT_EQ(written.images[i].stamp_s, d.images[i].stamp_s);
    EXPECT_EQ(written.images[i].file, d.images[i].file);
  }
  ASSERT_EQ(written.wheel_encoders.size(), d.wheel_encoders.size());
  for (std::size_t i = 0; i < d.wheel_encoders.size(); ++i) {
    EXPECT_EQ(written.wheel_encoders[i].stamp_s, d.wheel_encoders[i].stamp_s);
    EXPECT_NEAR(written.wheel_encoders[i].left_delta_rad, d.wheel_encoders[i].left_delta_rad,
                kAngleTol_rad);
    EXPECT_NEAR(written.wheel_encoders[i].right_delta_rad, d.wheel_encoders[i].right_delta_rad,
                kAngleTol_rad);
  }
  ExpectSameScans(written.scans, d.scans);
  ASSERT_EQ(written.ground_truth.size(), d.ground_truth.size());
  for (std::size_t i = 0; i < d.ground_truth.size(); ++i) {
    EXPECT_EQ(written.ground_truth[i].stamp_s, d.ground_truth[i].stamp_s);
    EXPECT_TRUE(written.ground_truth[i].pose.IsApprox(d.ground_truth[i].pose, 1e-9, 1e-10));
  }
  ASSERT_TRUE(d.floor_map.has_value());
  EXPECT_EQ(d.floor_map->frame, "map");
  ASSERT_TRUE(d.floor_map->survey.has_value());
  EXPECT_EQ(d.floor_map->survey->marking_vertex_sigma_m, 0.003);
  EXPECT_EQ(d.floor_map->survey->face_offset_sigma_m, 0.02);
  EXPECT_EQ(d.floor_map->survey->face_angle_sigma_rad, 0.0035);
  ASSERT_EQ(d.floor_map->markings.size(), written.floor_map->markings.size());
  for (std::size_t i = 0; i < d.floor_map->markings.size(); ++i) {
    const FloorMarking& a = written.floor_map->markings[i];
    const FloorMarking& b = d.floor_map->markings[i];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.width_m, b.width_m);
    EXPECT_EQ(a.colour_rgb, b.colour_rgb);
    EXPECT_EQ(a.polarity, b.polarity);
    EXPECT_EQ(a.polyline_m, b.polyline_m);
    EXPECT_EQ(a.dash_m, b.dash_m);
    EXPECT_EQ(a.gap_m, b.gap_m);
  }
  // Only the final files remain: no staging or temporary files.
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.find(".new"), std::string::npos) << name;
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
  }
}

TEST(Dataset, ManifestIsCommentedAndSaysItsUnits) {
  const std::filesystem::path dir = ScratchDir("manifest_text");
  ASSERT_TRUE(WriteDataset(dir, MakeSyntheticDataset(dir)).ok());
  const std::string text = ReadText(dir / kManifestFileName);
  EXPECT_EQ(text.rfind("# groundline dataset manifest", 0), 0u) << text;
  EXPECT_NE(text.find("format: groundline-dataset\nversion: 1.2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("units: SI"), std::string::npos);
  EXPECT_NE(text.find("T_base_lidar: {x_m: 0.3, y_m: -0.02, yaw_rad: "), std::string::npos) << text;
}

TEST(Dataset, ReadOptionsSkipPartsButStillCheckTheyExist) {
  const std::filesystem::path dir = ScratchDir("options");
  ASSERT_TRUE(WriteDataset(dir, MakeSyntheticDataset(dir)).ok());
  DatasetReadOptions options;
  options.load_scans = false;
  options.load_floor_map = false;
  const Result<Dataset> read = ReadDataset(dir, options);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_TRUE(read->scans.empty());
  EXPECT_FALSE(read->floor_map.has_value());
  EXPECT_EQ(read->images.size(), 5u);

  std::filesystem::remove(dir / kDefaultLidarScansFile);
  const Result<Dataset> missing = ReadDataset(dir, options);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("manifest.yaml:"), std::string::npos) << missing.message();
  EXPECT_NE(missing.message().find("field 'files.lidar_scans'"), std::string::npos)
      << missing.message();
  EXPECT_NE(missing.message().find("missing"), std::string::npos) << missing.message();
}

TEST(Dataset, DatasetWithoutOptionalSensorsRoundTrips) {
  const std::filesystem::path dir = ScratchDir("minimal");
  Dataset d;
  d.manifest.name = "lidar_only";
  d.manifest.lidar = LidarSensor{15.0, SE2(), 0.2, 0.1, 12.0};
  LaserScan scan;
  scan.stamp_s = 3.0;
  scan.angle_increment_rad = -0.01;  // a clockwise scanner
  scan.range_min_m = 0.1;
  scan.range_max_m = 12.0;
  scan.ranges_m = {0.0, 0.1, 11.99995, 12.0};
  d.scans = {scan};
  d.UseDefaultFileNames();
  EXPECT_TRUE(d.manifest.files.image_index.empty());
  EXPECT_TRUE(d.manifest.files.ground_truth.empty());
  ASSERT_TRUE(WriteDataset(dir, d).ok());
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_FALSE(read->manifest.camera.has_value());
  EXPECT_FALSE(read->floor_map.has_value());
  ExpectSameScans(d.scans, read->scans);
  EXPECT_TRUE(read->manifest.provenance.empty());
}

TEST(Dataset, GroundTruthOnlyDatasetRoundTrips) {
  const std::filesystem::path dir = ScratchDir("ground_truth_only");
  Dataset d;
  d.manifest.name = "poses";
  d.manifest.frames.base_link = "agv7/base_link";
  for (int i = 0; i < 3; ++i) d.ground_truth.push_back({0.5 * i, SE2(i, -i, 0.1 * i), {}});
  d.UseDefaultFileNames();
  ASSERT_TRUE(WriteDataset(dir, d).ok());
  EXPECT_NE(ReadText(dir / kManifestFileName).find("sensors: {}"), std::string::npos);
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->manifest.frames.base_link, "agv7/base_link");
  EXPECT_FALSE(read->manifest.camera || read->manifest.wheel_encoders || read->manifest.lidar);
  ASSERT_EQ(read->ground_truth.size(), 3u);
  EXPECT_TRUE(read->ground_truth[2].pose.IsApprox(SE2(2, -2, 0.2), 1e-9, 1e-10));
}

TEST(Dataset, SummaryReportsCountsRatesAndDistances) {
  const std::filesystem::path dir = ScratchDir("summary");
  const Dataset d = MakeSyntheticDataset(dir);
  const DatasetSummary s = SummarizeDataset(d);
  EXPECT_EQ(s.images.count, 5u);
  // Stamps near 1.7e9 s carry 2.4e-7 s of representation error.
  EXPECT_NEAR(s.images.mean_rate_hz, 10.0, 1e-4);
  EXPECT_EQ(s.wheel_encoders.count, 101u);
  EXPECT_NEAR(s.wheel_encoders.mean_rate_hz, 50.0, 1e-4);
  EXPECT_EQ(s.scans.count, 4u);
  EXPECT_NEAR(s.duration_s, 2.0, 1e-6);
  // 2 s at 1 m/s: the chords of the arc are a hair shorter than its length.
  EXPECT_NEAR(s.ground_truth_distance_m, 2.0, 1e-5);
  EXPECT_NEAR(s.wheel_distance_m, 2.0, 1e-9);
  // Beams with b % 17 == 3 have no return: 11 of 181.
  EXPECT_NEAR(s.scan_return_fraction, 170.0 / 181.0, 1e-12);
  EXPECT_EQ(s.floor_markings, 4u);
}

TEST(Dataset, LaserScanReaderStreamsScansWithTheirLines) {
  const std::filesystem::path dir = ScratchDir("stream");
  const Dataset d = MakeSyntheticDataset(dir);
  ASSERT_TRUE(WriteLaserScans(dir / "scans.txt", d.scans).ok());
  Result<LaserScanReader> reader = LaserScanReader::Open(dir / "scans.txt");
  ASSERT_TRUE(reader.ok()) << reader.message();
  std::vector<LaserScan> scans;
  LaserScan scan;
  while (true) {
    const Result<bool> more = reader->Next(&scan);
    ASSERT_TRUE(more.ok()) << more.message();
    if (!*more) break;
    EXPECT_EQ(reader->line(), scans.size() + 2);  // after the header line
    scans.push_back(scan);
  }
  ExpectSameScans(d.scans, scans);
}

TEST(Dataset, NewerMinorVersionIgnoresUnknownKeysCurrentOneRejectsThem) {
  const std::filesystem::path dir = ScratchDir("minor");
  ASSERT_TRUE(WriteDataset(dir, MakeSyntheticDataset(dir)).ok());
  const std::filesystem::path manifest = dir / kManifestFileName;
  ReplaceInFile(manifest, "units: SI", "units: SI\nweather: sunny");
  const Result<Dataset> strict = ReadDataset(dir);
  ASSERT_FALSE(strict.ok());
  EXPECT_NE(strict.message().find(manifest.string() + ":" +
                                  std::to_string(LineContaining(manifest, "weather")) +
                                  ": field 'weather'"),
            std::string::npos)
      << strict.message();
  ReplaceInFile(manifest, "version: 1.2", "version: 1.7");
  const Result<Dataset> lenient = ReadDataset(dir);
  ASSERT_TRUE(lenient.ok()) << lenient.message();
  EXPECT_EQ(lenient->manifest.version_minor, 7);
}

TEST(Dataset, ValidateNamesTheBrokenRule) {
  DatasetManifest m;
  m.name = "x";
  m.lidar = LidarSensor{10.0, SE2(), 0.2, 0.05, 30.0};
  const Status unpaired = m.Validate();
  ASSERT_FALSE(unpaired.ok());
  EXPECT_NE(unpaired.message().find("files.lidar_scans"), std::string::npos) << unpaired.message();
  m.files.lidar_scans = "scans.txt";
  EXPECT_TRUE(m.Validate().ok()) << m.Validate().message();
  m.lidar->range_min_m = 0.0;
  EXPECT_NE(m.Validate().message().find("sensors.lidar.range_min_m"), std::string::npos);
  m.lidar->range_min_m = 0.05;
  m.files.ground_truth = "../outside.tum";
  EXPECT_NE(m.Validate().message().find("files.ground_truth"), std::string::npos);
  m.files.ground_truth = "scans.txt";
  EXPECT_NE(m.Validate().message().find("a file other than files.lidar_scans"), std::string::npos)
      << m.Validate().message();
}

}  // namespace
}  // namespace groundline::core
