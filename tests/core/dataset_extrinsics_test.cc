// ground_truth_extrinsics.csv (format 1.1): round trip through the dataset,
// 1.0 manifests still read, and damaged files named by file, line and field.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "dataset_fixture.h"
#include "groundline/core/dataset.h"
#include "test_data.h"

namespace groundline::core {
namespace {

namespace fs = std::filesystem;
using ::groundline::testing::LineContaining;
using ::groundline::testing::ReadLines;
using ::groundline::testing::ReplaceInFile;
using ::groundline::testing::WriteLines;
using ::groundline::testing::WriteText;

// The synthetic dataset with a knock at 1 s: the mount changes once.
Dataset WithExtrinsics(const fs::path& dir) {
  Dataset d = ::groundline::testing::MakeSyntheticDataset(dir);
  const double t0_s = d.ground_truth.front().stamp_s;
  d.ground_truth_extrinsics = {{t0_s, 0.58, 0.74, 0.0, 0.0, 0.42, 0.0},
                               {t0_s + 1.0, 0.5795, 0.7312345678, -0.0052, 0.0175, 0.42, 0.001}};
  d.UseDefaultFileNames();
  return d;
}

TEST(DatasetExtrinsics, RoundTripsAtTheWrittenPrecision) {
  const fs::path dir = ::groundline::testing::ScratchDir("extrinsics_round_trip");
  const Dataset written = WithExtrinsics(dir);
  ASSERT_TRUE(WriteDataset(dir, written).ok());
  EXPECT_TRUE(fs::is_regular_file(dir / kDefaultGroundTruthExtrinsicsFile));
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->manifest.version_minor, kDatasetFormatMinor);
  EXPECT_EQ(read->manifest.files.ground_truth_extrinsics, kDefaultGroundTruthExtrinsicsFile);
  ASSERT_EQ(read->ground_truth_extrinsics.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const CameraExtrinsicsRecord& a = written.ground_truth_extrinsics[i];
    const CameraExtrinsicsRecord& b = read->ground_truth_extrinsics[i];
    EXPECT_NEAR(b.stamp_s, a.stamp_s, 3e-7);  // epoch-like stamps: double resolution
    EXPECT_NEAR(b.height_m, a.height_m, 1e-9);
    EXPECT_NEAR(b.pitch_rad, a.pitch_rad, 1e-9);
    EXPECT_NEAR(b.roll_rad, a.roll_rad, 1e-9);
    EXPECT_NEAR(b.yaw_rad, a.yaw_rad, 1e-9);
    EXPECT_NEAR(b.forward_m, a.forward_m, 1e-9);
    EXPECT_NEAR(b.lateral_m, a.lateral_m, 1e-9);
  }
}

TEST(DatasetExtrinsics, Version10ManifestsStillRead) {
  const fs::path dir = ::groundline::testing::ScratchDir("extrinsics_v10");
  ASSERT_TRUE(WriteDataset(dir, ::groundline::testing::MakeSyntheticDataset(dir)).ok());
  ReplaceInFile(dir / kManifestFileName, "version: 1.2", "version: 1.0");
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->manifest.version_minor, 0);
  EXPECT_TRUE(read->ground_truth_extrinsics.empty());
}

TEST(DatasetExtrinsics, WithoutACameraIsRejected) {
  const fs::path dir = ::groundline::testing::ScratchDir("extrinsics_no_camera");
  Dataset d = WithExtrinsics(dir);
  d.manifest.camera.reset();
  d.images.clear();
  d.UseDefaultFileNames();
  const Status s = WriteDataset(dir, d);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("files.ground_truth_extrinsics"), std::string::npos) << s.message();
}

struct Damage {
  std::string name;
  // Damages the file and returns the line the error must name.
  std::function<std::size_t(const fs::path& file)> apply;
  std::string field;
};
void PrintTo(const Damage& d, std::ostream* os) { *os << d.name; }

std::size_t SetLine(const fs::path& file, std::size_t line, const std::string& text) {
  std::vector<std::string> lines = ReadLines(file);
  lines[line - 1] = text;
  WriteLines(file, lines);
  return line;
}

std::vector<Damage> Damages() {
  return {
      {"nan_pitch",
       [](const fs::path& f) { return SetLine(f, 3, "1700000001,0.58,nan,0,0,0.42,0"); },
       "pitch_rad"},
      {"negative_height",
       [](const fs::path& f) { return SetLine(f, 2, "1700000000,-0.58,0.74,0,0,0.42,0"); },
       "height_m"},
      {"pitch_at_horizon",
       [](const fs::path& f) { return SetLine(f, 3, "1700000001,0.58,1.6,0,0,0.42,0"); },
       "pitch_rad"},
      {"yaw_out_of_range",
       [](const fs::path& f) { return SetLine(f, 3, "1700000001,0.58,0.7,0,4,0.42,0"); },
       "yaw_rad"},
      {"missing_field",
       [](const fs::path& f) { return SetLine(f, 3, "1700000001,0.58,0.7,0,0,0.42"); }, "line"},
      {"stamps_decrease",
       [](const fs::path& f) { return SetLine(f, 3, "1699999999,0.58,0.7,0,0,0.42,0"); },
       "stamp_s"},
      {"bad_header", [](const fs::path& f) { return SetLine(f, 1, "stamp_s,height_m,pitch_rad"); },
       "header"},
      {"cut_mid_line",
       [](const fs::path& f) {
         std::vector<std::string> lines = ReadLines(f);
         WriteText(f, lines[0] + "\n" + lines[1] + "\n" + lines[2].substr(0, 12));
         return std::size_t{3};
       },
       ""},
  };
}

class DatasetExtrinsicsDamaged : public ::testing::TestWithParam<Damage> {};

TEST_P(DatasetExtrinsicsDamaged, ErrorNamesFileLineAndField) {
  const Damage& damage = GetParam();
  const fs::path dir = ::groundline::testing::ScratchDir("extrinsics_" + damage.name);
  ASSERT_TRUE(WriteDataset(dir, WithExtrinsics(dir)).ok());
  const fs::path file = dir / kDefaultGroundTruthExtrinsicsFile;
  const std::size_t line = damage.apply(file);
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_FALSE(read.ok()) << "accepted damage '" << damage.name << "'";
  const std::string location = file.string() + ":" + std::to_string(line) + ":";
  EXPECT_NE(read.message().find(location), std::string::npos) << "want " << location << "\n"
                                                              << read.message();
  if (!damage.field.empty()) {
    EXPECT_NE(read.message().find("'" + damage.field + "'"), std::string::npos) << read.message();
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, DatasetExtrinsicsDamaged, ::testing::ValuesIn(Damages()),
                         [](const ::testing::TestParamInfo<Damage>& info) {
                           return info.param.name;
                         });

TEST(DatasetExtrinsics, MissingFileIsNamedInTheManifest) {
  const fs::path dir = ::groundline::testing::ScratchDir("extrinsics_missing");
  ASSERT_TRUE(WriteDataset(dir, WithExtrinsics(dir)).ok());
  fs::remove(dir / kDefaultGroundTruthExtrinsicsFile);
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_FALSE(read.ok());
  const fs::path manifest = dir / kManifestFileName;
  EXPECT_NE(
      read.message().find(manifest.string() + ":" +
                          std::to_string(LineContaining(manifest, "ground_truth_extrinsics")) +
                          ": field 'files.ground_truth_extrinsics'"),
      std::string::npos)
      << read.message();
}

}  // namespace
}  // namespace groundline::core
