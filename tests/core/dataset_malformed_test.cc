// Every malformed dataset must be rejected with a message that names the
// file, the line and the field. Each case starts from a valid written dataset
// and damages one file the way real files get damaged.
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

struct Corruption {
  std::string name;
  std::string file;  // the file the message must name, relative to the dataset
  // Damages the dataset in `dir` and returns the line the error must name.
  std::function<std::size_t(const fs::path& dir)> corrupt;
  std::string field;
  std::string also = "";  // another substring the message must contain
};

// Replaces field `index` (0-based, split on `separator`) of line `line`.
std::size_t SetToken(const fs::path& path, std::size_t line, std::size_t index, char separator,
                     const std::string& value) {
  std::vector<std::string> lines = ReadLines(path);
  std::vector<std::string> tokens;
  std::string token;
  for (char c : lines[line - 1] + separator) {
    if (c == separator) {
      tokens.push_back(token);
      token.clear();
    } else {
      token += c;
    }
  }
  tokens[index] = value;
  std::string joined;
  for (std::size_t i = 0; i < tokens.size(); ++i)
    joined += (i ? std::string(1, separator) : "") + tokens[i];
  lines[line - 1] = joined;
  WriteLines(path, lines);
  return line;
}

std::size_t SwapLines(const fs::path& path, std::size_t a) {
  std::vector<std::string> lines = ReadLines(path);
  std::swap(lines[a - 1], lines[a]);
  WriteLines(path, lines);
  return a + 1;  // the second of the two is the first out of order
}

// Cuts the file `keep` characters into its last line (no final newline).
std::size_t CutLastLine(const fs::path& path, std::size_t keep) {
  std::vector<std::string> lines = ReadLines(path);
  std::string text;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) text += lines[i] + "\n";
  text += lines.back().substr(0, keep);
  WriteText(path, text);
  return lines.size();
}

std::size_t Replace(const fs::path& path, const std::string& from, const std::string& to) {
  ReplaceInFile(path, from, to);
  return LineContaining(path, to.empty() ? from : to);
}

std::vector<Corruption> Cases() {
  const std::string scans = kDefaultLidarScansFile, wheels = kDefaultWheelEncodersFile;
  const std::string index = kDefaultImageIndexFile, gt = kDefaultGroundTruthFile;
  const std::string map = kDefaultFloorMapFile, manifest = kManifestFileName;
  return {
      // Truncated files.
      {"scan_fewer_ranges_than_count", scans,
       [=](const fs::path& d) {
         std::vector<std::string> lines = ReadLines(d / scans);
         lines[2] = lines[2].substr(0, lines[2].find(' ', 700));
         WriteLines(d / scans, lines);
         return std::size_t{3};
       },
       "ranges_m", "181 ranges"},
      {"scan_cut_mid_line", scans, [=](const fs::path& d) { return CutLastLine(d / scans, 400); },
       "line", "cut mid-way"},
      {"wheels_cut_mid_line", wheels,
       [=](const fs::path& d) { return CutLastLine(d / wheels, 25); }, "line", "cut mid-way"},
      {"ground_truth_cut_mid_line", gt, [=](const fs::path& d) { return CutLastLine(d / gt, 30); },
       "line", "cut mid-way"},
      {"scan_intensity_count", scans,
       [=](const fs::path& d) { return SetToken(d / scans, 2, 6 + 181, ' ', "180"); }, "m",
       "0 or n = 181"},
      // Reordered records.
      {"wheels_reordered", wheels, [=](const fs::path& d) { return SwapLines(d / wheels, 10); },
       "stamp_s", "strictly increasing"},
      {"images_reordered", index, [=](const fs::path& d) { return SwapLines(d / index, 3); },
       "stamp_s"},
      {"scans_reordered", scans, [=](const fs::path& d) { return SwapLines(d / scans, 3); },
       "stamp_s"},
      {"ground_truth_reordered", gt, [=](const fs::path& d) { return SwapLines(d / gt, 5); }, "t"},
      // NaN and inf anywhere.
      {"wheels_nan", wheels,
       [=](const fs::path& d) { return SetToken(d / wheels, 7, 1, ',', "nan"); }, "left_delta_rad",
       "finite"},
      {"wheels_inf", wheels,
       [=](const fs::path& d) { return SetToken(d / wheels, 9, 2, ',', "inf"); },
       "right_delta_rad"},
      {"image_stamp_nan", index,
       [=](const fs::path& d) { return SetToken(d / index, 2, 0, ',', "nan"); }, "stamp_s"},
      {"scan_range_nan", scans,
       [=](const fs::path& d) { return SetToken(d / scans, 4, 6 + 5, ' ', "nan"); }, "ranges_m[5]"},
      {"scan_intensity_inf", scans,
       [=](const fs::path& d) { return SetToken(d / scans, 2, 6 + 181 + 1 + 3, ' ', "inf"); },
       "intensities[3]"},
      {"ground_truth_nan", gt,
       [=](const fs::path& d) { return SetToken(d / gt, 8, 1, ' ', "nan"); }, "x"},
      {"manifest_rate_nan", manifest,
       [=](const fs::path& d) { return Replace(d / manifest, "rate_hz: 10", "rate_hz: .nan"); },
       "sensors.camera.rate_hz", "finite"},
      {"floor_map_nan", map,
       [=](const fs::path& d) { return Replace(d / map, "[[0, 1.2]", "[[.nan, 1.2]"); },
       "markings[0].polyline_m[0][0]"},
      // Values out of their documented range.
      {"scan_range_beyond_max", scans,
       [=](const fs::path& d) { return SetToken(d / scans, 5, 6 + 7, ' ', "31.0000"); },
       "ranges_m[7]", "0 (no return)"},
      {"scan_limits_differ_from_manifest", scans,
       [=](const fs::path& d) { return SetToken(d / scans, 3, 4, ' ', "35.0000"); }, "range_max_m",
       "sensors.lidar.range_max_m"},
      {"ground_truth_non_unit_quaternion", gt,
       [=](const fs::path& d) { return SetToken(d / gt, 4, 7, ' ', "0.5"); }, "quaternion"},
      // Mislabelled files.
      {"image_index_header", index,
       [=](const fs::path& d) { return Replace(d / index, "stamp_s,file", "time,file"); },
       "header"},
      {"wheels_columns_swapped", wheels,
       [=](const fs::path& d) {
         return Replace(d / wheels, "stamp_s,left_delta_rad,right_delta_rad",
                        "stamp_s,right_delta_rad,left_delta_rad");
       },
       "header"},
      {"scans_header", scans,
       [=](const fs::path& d) { return Replace(d / scans, "lidar_scans v1", "lidar_scans v0"); },
       "header"},
      {"manifest_format_name", manifest,
       [=](const fs::path& d) {
         return Replace(d / manifest, "format: groundline-dataset", "format: groundline-atlas");
       },
       "format", "groundline-atlas"},
      {"manifest_higher_version", manifest,
       [=](const fs::path& d) { return Replace(d / manifest, "version: 1.2", "version: 2.0"); },
       "version", "newer groundline"},
      {"manifest_lidar_rate_zero", manifest,
       [=](const fs::path& d) { return Replace(d / manifest, "rate_hz: 12.5", "rate_hz: 0"); },
       "sensors.lidar.rate_hz", "a rate in (0, 1000] Hz"},
      {"manifest_camera_rate_absurd", manifest,
       [=](const fs::path& d) { return Replace(d / manifest, "rate_hz: 10", "rate_hz: 1e6"); },
       "sensors.camera.rate_hz", "a rate in (0, 1000] Hz"},
      {"manifest_lidar_rate_absurd", manifest,
       [=](const fs::path& d) { return Replace(d / manifest, "rate_hz: 12.5", "rate_hz: 12500"); },
       "sensors.lidar.rate_hz", "a rate in (0, 1000] Hz"},
      {"manifest_lidar_mount_height_in_mm", manifest,
       [=](const fs::path& d) {
         return Replace(d / manifest, "mount_height_m: 0.2", "mount_height_m: 200");
       },
       "sensors.lidar.mount_height_m", "a height in [0, 5] m"},
      {"manifest_camera_rate_negative", manifest,
       [=](const fs::path& d) { return Replace(d / manifest, "rate_hz: 10", "rate_hz: -10"); },
       "sensors.camera.rate_hz", "a rate in (0, 1000] Hz"},
      {"manifest_units", manifest,
       [=](const fs::path& d) { return Replace(d / manifest, "units: SI", "units: mm"); }, "units"},
      {"manifest_key_typo", manifest,
       [=](const fs::path& d) {
         return Replace(d / manifest, "ticks_per_rev:", "ticks_per_revolution:");
       },
       "sensors.wheel_encoders.ticks_per_revolution", "unknown key"},
      {"floor_map_dashed_without_gap", map,
       [=](const fs::path& d) {
         Replace(d / map, "    gap_m: 0.25\n", "");
         return LineContaining(d / map, "id: 7");
       },
       "markings[0].gap_m"},
      {"floor_map_duplicate_id", map,
       [=](const fs::path& d) {
         Replace(d / map, "id: 8", "id: 7");
         return LineContaining(d / map, "kind: stop_bar") - 1;
       },
       "markings[1].id", "unique"},
      {"floor_map_frame", map,
       [=](const fs::path& d) { return Replace(d / map, "frame: \"map\"", "frame: \"world\""); },
       "frame", "map frame"},
      // YAML is UTF-8: other bytes could not be written back (found by fuzzing).
      {"floor_map_frame_not_utf8", map,
       [=](const fs::path& d) { return Replace(d / map, "frame: \"map\"", "frame: \"ma\xffp\""); },
       "frame", "UTF-8"},
      {"floor_map_survey_sigma_zero", map,
       [=](const fs::path& d) {
         return Replace(d / map, "face_offset_sigma_m: 0.02", "face_offset_sigma_m: 0");
       },
       "survey.face_offset_sigma_m", "sigma > 0"},
      {"floor_map_survey_unknown_key", map,
       [=](const fs::path& d) {
         return Replace(d / map, "face_angle_sigma_rad:", "face_angle_sigma_deg:");
       },
       "survey.face_angle_sigma_deg", "unknown key"},
      {"floor_map_unknown_kind", map,
       [=](const fs::path& d) { return Replace(d / map, "kind: joint", "kind: pothole"); },
       "markings[2].kind"},
      // Referenced files missing.
      {"missing_calibration", manifest,
       [=](const fs::path& d) {
         fs::remove(d / "calibration/extrinsics.yaml");
         return LineContaining(d / manifest, "extrinsics_file:");
       },
       "sensors.camera.extrinsics_file", "missing"},
      {"missing_stream_file", manifest,
       [=](const fs::path& d) {
         fs::remove(d / wheels);
         return LineContaining(d / manifest, "wheel_encoders: \"");
       },
       "files.wheel_encoders", "missing"},
      {"missing_image", index,
       [=](const fs::path& d) {
         fs::remove(d / "images/000002.png");
         return LineContaining(d / index, "000002.png");
       },
       "file", "existing image"},
  };
}

// Keeps the ctest names short: gtest_discover_tests appends the printed parameter.
void PrintTo(const Corruption& c, std::ostream* os) { *os << c.name; }

class DatasetMalformed : public ::testing::TestWithParam<Corruption> {};

TEST_P(DatasetMalformed, ErrorNamesFileLineAndField) {
  const Corruption& c = GetParam();
  const fs::path dir = ::groundline::testing::ScratchDir(c.name);
  const Status written = WriteDataset(dir, ::groundline::testing::MakeSyntheticDataset(dir));
  ASSERT_TRUE(written.ok()) << written.message();
  const std::size_t line = c.corrupt(dir);
  ASSERT_GT(line, 0u);
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_FALSE(read.ok()) << "accepted a dataset with damage '" << c.name << "'";
  const std::string& message = read.message();
  const std::string location = (dir / c.file).string() + ":" + std::to_string(line) + ":";
  EXPECT_NE(message.find(location), std::string::npos) << "want " << location << "\n" << message;
  EXPECT_NE(message.find("field '" + c.field + "'"), std::string::npos) << message;
  EXPECT_NE(message.find(c.also), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Cases, DatasetMalformed, ::testing::ValuesIn(Cases()),
                         [](const ::testing::TestParamInfo<Corruption>& info) {
                           return info.param.name;
                         });

TEST(DatasetMalformedManifest, MissingManifestSaysItIsNoDataset) {
  const fs::path dir = ::groundline::testing::ScratchDir("no_manifest");
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.message().find("no manifest.yaml"), std::string::npos) << read.message();
}

TEST(DatasetMalformedManifest, YamlSyntaxErrorNamesTheLine) {
  const fs::path dir = ::groundline::testing::ScratchDir("syntax");
  ASSERT_TRUE(WriteDataset(dir, ::groundline::testing::MakeSyntheticDataset(dir)).ok());
  ReplaceInFile(dir / kManifestFileName, "units: SI", "units: [SI");
  const Result<Dataset> read = ReadDataset(dir);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.message().find((dir / kManifestFileName).string() + ":"), std::string::npos)
      << read.message();
  EXPECT_NE(read.message().find("YAML syntax error"), std::string::npos) << read.message();
}

}  // namespace
}  // namespace groundline::core
