// WriteDataset validates before it writes, names the file, line and field of
// what it rejects, leaves an existing dataset untouched on a validation error,
// and writes the manifest last.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <ostream>
#include <string>

#include "dataset_fixture.h"
#include "groundline/core/dataset.h"
#include "test_data.h"

namespace groundline::core {
namespace {

namespace fs = std::filesystem;
using ::groundline::testing::MakeSyntheticDataset;
using ::groundline::testing::ReadText;
using ::groundline::testing::ScratchDir;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Every file of `dir` with its content, to compare a directory before/after.
std::map<std::string, std::string> Snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) {
      files[fs::relative(entry.path(), dir).string()] = ReadText(entry.path());
    }
  }
  return files;
}

struct BadWrite {
  std::string name;
  std::function<void(Dataset*, const fs::path& dir)> damage;
  std::string must_contain;  // "<file>:<line>: field '<field>'" or a phrase
};

// Keeps the ctest names short: gtest_discover_tests appends the printed parameter.
void PrintTo(const BadWrite& c, std::ostream* os) { *os << c.name; }

class DatasetWriteRejects : public ::testing::TestWithParam<BadWrite> {};

TEST_P(DatasetWriteRejects, AndLeavesTheExistingDatasetUntouched) {
  const BadWrite& c = GetParam();
  const fs::path dir = ScratchDir(c.name);
  Dataset d = MakeSyntheticDataset(dir);
  d.manifest.name = "first";
  ASSERT_TRUE(WriteDataset(dir, d).ok());
  const auto before = Snapshot(dir);

  d.manifest.name = "second";
  c.damage(&d, dir);
  const auto files_before_write = Snapshot(dir);
  const Status status = WriteDataset(dir, d);
  ASSERT_FALSE(status.ok());
  const std::string expected = c.must_contain.find(':') != std::string::npos
                                   ? (dir / c.must_contain).string()
                                   : c.must_contain;
  EXPECT_NE(status.message().find(expected), std::string::npos) << "want '" << expected << "' in\n"
                                                                << status.message();
  EXPECT_EQ(status.message().find(".new"), std::string::npos) << status.message();
  EXPECT_EQ(Snapshot(dir), files_before_write) << "the directory changed";
  // The first dataset is still complete and readable (unless damage() removed
  // one of its inputs, which only the later write needed).
  if (files_before_write == before) {
    const Result<Dataset> read = ReadDataset(dir);
    ASSERT_TRUE(read.ok()) << read.message();
    EXPECT_EQ(read->manifest.name, "first");
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, DatasetWriteRejects,
    ::testing::Values(
        BadWrite{"nan_range", [](Dataset* d, const fs::path&) { d->scans[1].ranges_m[4] = kNaN; },
                 "lidar_scans.txt:3: field 'ranges_m[4]'"},
        BadWrite{"range_beyond_limit",
                 [](Dataset* d, const fs::path&) { d->scans[0].ranges_m[2] = 30.5; },
                 "lidar_scans.txt:2: field 'ranges_m[2]'"},
        BadWrite{"intensity_count",
                 [](Dataset* d, const fs::path&) { d->scans[3].intensities.pop_back(); },
                 "lidar_scans.txt:5: field 'm'"},
        // Distinct in memory, equal once written with 9 decimals.
        BadWrite{"stamps_closer_than_1ns",
                 [](Dataset* d, const fs::path&) {
                   d->wheel_encoders[5].stamp_s = 1.0;
                   d->wheel_encoders[4].stamp_s = 1.0 - 1e-11;
                   for (int i = 0; i < 4; ++i) d->wheel_encoders[i].stamp_s = 0.1 * i;
                 },
                 "wheel_encoders.csv:7: field 'stamp_s'"},
        BadWrite{"inf_delta",
                 [](Dataset* d, const fs::path&) {
                   d->wheel_encoders[2].right_delta_rad = std::numeric_limits<double>::infinity();
                 },
                 "wheel_encoders.csv:4: field 'right_delta_rad'"},
        BadWrite{"unordered_images",
                 [](Dataset* d, const fs::path&) { std::swap(d->images[1], d->images[2]); },
                 "images/index.csv:4: field 'stamp_s'"},
        BadWrite{"missing_image",
                 [](Dataset* d, const fs::path&) { d->images[4].file = "missing.png"; },
                 "images/index.csv:6: field 'file'"},
        BadWrite{"image_outside_dataset",
                 [](Dataset* d, const fs::path&) { d->images[0].file = "../000000.png"; },
                 "images/index.csv:2: field 'file'"},
        BadWrite{"comma_in_image_name",
                 [](Dataset* d, const fs::path& dir) {
                   d->images[1].file = "a,b.png";
                   ::groundline::testing::WriteText(dir / "images/a,b.png", "fixture\n");
                 },
                 "images/index.csv:3: field 'file'"},
        BadWrite{"nan_ground_truth",
                 [](Dataset* d, const fs::path&) { d->ground_truth[3].stamp_s = kNaN; },
                 "non-finite"},
        BadWrite{"floor_map_width",
                 [](Dataset* d, const fs::path&) { d->floor_map->markings[1].width_m = 0.0; },
                 "field 'markings[1].width_m'"},
        BadWrite{"manifest_rate",
                 [](Dataset* d, const fs::path&) { d->manifest.wheel_encoders->rate_hz = -1; },
                 "field 'sensors.wheel_encoders.rate_hz'"},
        BadWrite{"scans_without_file_name",
                 [](Dataset* d, const fs::path&) {
                   d->manifest.lidar.reset();
                   d->manifest.files.lidar_scans.clear();
                 },
                 "dataset has 4 scans but manifest.files.lidar_scans is empty"},
        BadWrite{"missing_calibration",
                 [](Dataset*, const fs::path& dir) { fs::remove(dir / "calibration/camera.yaml"); },
                 "calibration/camera.yaml"}),
    [](const ::testing::TestParamInfo<BadWrite>& info) { return info.param.name; });

TEST(DatasetWrite, OverwritesAnExistingDataset) {
  const fs::path dir = ScratchDir("overwrite");
  Dataset d = MakeSyntheticDataset(dir);
  ASSERT_TRUE(WriteDataset(dir, d).ok());
  d.manifest.name = "second";
  d.scans.pop_back();
  d.floor_map.reset();
  d.UseDefaultFileNames();
  ASSERT_TRUE(WriteDataset(dir, d).ok());
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->manifest.name, "second");
  EXPECT_EQ(read->scans.size(), 3u);
  EXPECT_FALSE(read->floor_map.has_value());
}

TEST(DatasetWrite, ManifestIsNoOlderThanAnyDataFile) {
  const fs::path dir = ScratchDir("mtime");
  ASSERT_TRUE(WriteDataset(dir, MakeSyntheticDataset(dir)).ok());
  const fs::file_time_type manifest_time = fs::last_write_time(dir / kManifestFileName);
  for (const char* file : {kDefaultImageIndexFile, kDefaultWheelEncodersFile,
                           kDefaultLidarScansFile, kDefaultGroundTruthFile, kDefaultFloorMapFile}) {
    EXPECT_LE(fs::last_write_time(dir / file), manifest_time) << file;
  }
}

TEST(DatasetWrite, FailureWhileMovingFilesLeavesNoManifest) {
  const fs::path dir = ScratchDir("no_manifest_after_failure");
  const Dataset d = MakeSyntheticDataset(dir);
  ASSERT_TRUE(WriteDataset(dir, d).ok());
  // A non-empty directory where floor_map.yaml goes: the rename into place
  // fails after the old manifest was retired and some files were replaced.
  fs::remove(dir / kDefaultFloorMapFile);
  fs::create_directories(dir / kDefaultFloorMapFile / "blocker");
  const Status status = WriteDataset(dir, d);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("floor_map.yaml"), std::string::npos) << status.message();
  EXPECT_FALSE(fs::exists(dir / kManifestFileName));
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.message().find("no manifest.yaml"), std::string::npos) << read.message();
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    EXPECT_EQ(entry.path().string().find(".new"), std::string::npos) << entry.path();
  }
}

TEST(FloorMap, ValidateNamesTheMarking) {
  FloorMap map;
  FloorMarking m;
  m.id = 3;
  m.width_m = 0.05;
  m.polyline_m = {Vector2(0, 0), Vector2(0.0005, 0)};
  map.markings = {m};
  const Status status = map.Validate();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("markings[0].polyline_m[1]"), std::string::npos)
      << status.message();
  map.markings[0].polyline_m[1] = Vector2(2, 0);
  EXPECT_TRUE(map.Validate().ok()) << map.Validate().message();
  map.markings[0].dash_m = 0.3;  // a dash pattern on a solid line
  EXPECT_NE(map.Validate().message().find("markings[0].dash_m"), std::string::npos);
}

TEST(FloorMap, KindNamesRoundTrip) {
  for (MarkingKind kind :
       {MarkingKind::kTapeSolid, MarkingKind::kTapeDashed, MarkingKind::kStopBar,
        MarkingKind::kCrosswalkStripe, MarkingKind::kStagingBoxEdge, MarkingKind::kJoint}) {
    EXPECT_EQ(MarkingKindFromName(MarkingKindName(kind)), kind);
  }
  EXPECT_FALSE(MarkingKindFromName("Tape_Solid").has_value());
}

}  // namespace
}  // namespace groundline::core
