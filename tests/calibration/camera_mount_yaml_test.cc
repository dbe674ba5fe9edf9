#include "groundline/calibration/camera_mount_yaml.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>

#include "test_data.h"
#include "test_units.h"

namespace groundline::calibration {
namespace {

using ::groundline::testing::kPi;

const char kExample[] =
    "format: groundline_camera_extrinsics\n"
    "version: 1\n"
    "height_m: 0.58\n"
    "pitch_deg: 42.4\n"
    "roll_deg: 0\n"
    "yaw_deg: 0\n"
    "forward_m: 0.42\n"
    "lateral_m: 0\n";

// The example with the line that starts with `key` replaced (or dropped if empty).
std::string ExampleWith(const std::string& key, const std::string& line) {
  std::string out;
  std::string text = kExample;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = text.find('\n', start);
    const std::string current = text.substr(start, end - start);
    if (current.rfind(key + ":", 0) == 0) {
      if (!line.empty()) out += line + "\n";
    } else {
      out += current + "\n";
    }
    start = end + 1;
  }
  return out;
}

void ExpectError(const std::string& text, const std::string& fragment) {
  const core::Result<CameraMount> mount = ParseCameraMountYaml(text, "mount.yaml");
  ASSERT_FALSE(mount.ok()) << "accepted:\n" << text;
  EXPECT_NE(mount.message().find(fragment), std::string::npos)
      << "message '" << mount.message() << "' lacks '" << fragment << "'";
}

TEST(CameraMountYaml, ParsesTheDocumentedExample) {
  const core::Result<CameraMount> mount = ParseCameraMountYaml(kExample, "example.yaml");
  ASSERT_TRUE(mount.ok()) << mount.message();
  EXPECT_EQ(mount->height_m, 0.58);
  EXPECT_NEAR(mount->pitch_rad, 42.4 * kPi / 180.0, 1e-15);
  EXPECT_EQ(mount->roll_rad, 0.0);
  EXPECT_EQ(mount->yaw_rad, 0.0);
  EXPECT_EQ(mount->forward_m, 0.42);
  EXPECT_EQ(mount->lateral_m, 0.0);
}

TEST(CameraMountYaml, WriteThenReadRoundTripsRandomMounts) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("yaml");
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    CameraMount mount;
    mount.height_m = 1.0 + 0.9 * unit(rng);
    mount.pitch_rad = 1.5 * unit(rng);
    mount.roll_rad = kPi * unit(rng);
    mount.yaw_rad = kPi * unit(rng);
    mount.forward_m = unit(rng);
    mount.lateral_m = unit(rng);
    const std::filesystem::path path = dir / "extrinsics.yaml";
    ASSERT_TRUE(WriteCameraMountYaml(mount, path).ok());
    EXPECT_FALSE(std::filesystem::exists(dir / "extrinsics.yaml.tmp"));
    const core::Result<CameraMount> back = ReadCameraMountYaml(path);
    ASSERT_TRUE(back.ok()) << back.message();
    // Lengths are stored exactly; angles pass through degrees (a few ulp).
    EXPECT_EQ(back->height_m, mount.height_m);
    EXPECT_EQ(back->forward_m, mount.forward_m);
    EXPECT_EQ(back->lateral_m, mount.lateral_m);
    EXPECT_NEAR(back->pitch_rad, mount.pitch_rad, 1e-14);
    EXPECT_NEAR(back->roll_rad, mount.roll_rad, 1e-14);
    EXPECT_NEAR(back->yaw_rad, mount.yaw_rad, 1e-14);
  }
}

TEST(CameraMountYaml, WritesReadableNumbers) {
  const std::string text = CameraMountToYaml(CameraMount{});
  EXPECT_NE(text.find("height_m: 0.58\n"), std::string::npos) << text;
  EXPECT_NE(text.find("pitch_deg: 42.4\n"), std::string::npos) << text;
  EXPECT_NE(text.find("forward_m: 0.42\n"), std::string::npos) << text;
}

TEST(CameraMountYaml, HalfTurnAnglesAreAccepted) {
  const core::Result<CameraMount> mount =
      ParseCameraMountYaml(ExampleWith("yaw_deg", "yaw_deg: -180"), "mount.yaml");
  ASSERT_TRUE(mount.ok()) << mount.message();
  EXPECT_EQ(mount->yaw_rad, -kPi);
}

TEST(CameraMountYaml, MissingKeyIsNamed) {
  ExpectError(ExampleWith("pitch_deg", ""), "mount.yaml: missing key 'pitch_deg'");
  ExpectError(ExampleWith("version", ""), "missing key 'version'");
}

TEST(CameraMountYaml, NonNumberIsNamedWithItsLine) {
  ExpectError(ExampleWith("height_m", "height_m: abc"),
              "mount.yaml:3: key 'height_m': expected a finite number, got 'abc'");
  ExpectError(ExampleWith("roll_deg", "roll_deg: [1, 2]"), "key 'roll_deg': expected a finite");
  ExpectError(ExampleWith("lateral_m", "lateral_m: .nan"), "key 'lateral_m'");
  ExpectError(ExampleWith("forward_m", "forward_m:"), "key 'forward_m'");
}

TEST(CameraMountYaml, OutOfRangeValuesAreRejected) {
  ExpectError(ExampleWith("height_m", "height_m: -0.58"), "mount.yaml:3: key 'height_m'");
  ExpectError(ExampleWith("pitch_deg", "pitch_deg: 90"), "key 'pitch_deg': expected |pitch| < 90");
  ExpectError(ExampleWith("yaw_deg", "yaw_deg: 181"), "key 'yaw_deg'");
}

// A height of 58 (0.58 m written in the wrong unit) or a non-finite value is
// refused with the field, the range expected and the value given.
TEST(CameraMountYaml, AbsurdOrNonFiniteLengthsNameTheFieldAndTheRange) {
  ExpectError(ExampleWith("height_m", "height_m: 58"),
              "mount.yaml:3: key 'height_m': expected a height above the floor in (0, 5] m "
              "(metres, not mm or cm), got 58");
  ExpectError(ExampleWith("height_m", "height_m: .inf"),
              "mount.yaml:3: key 'height_m': expected a finite number, got '.inf'");
  ExpectError(ExampleWith("forward_m", "forward_m: 420"),
              "key 'forward_m': expected an offset ahead of base_link in [-10, 10] m");
  ExpectError(ExampleWith("lateral_m", "lateral_m: -11"),
              "key 'lateral_m': expected an offset left of base_link in [-10, 10] m");
  // The limits themselves are mounts.
  EXPECT_TRUE(ParseCameraMountYaml(ExampleWith("height_m", "height_m: 5"), "m.yaml").ok());
  EXPECT_TRUE(ParseCameraMountYaml(ExampleWith("forward_m", "forward_m: -10"), "m.yaml").ok());
}

TEST(CameraMountYaml, WrongFormatVersionAndUnknownKeysAreRejected) {
  ExpectError(ExampleWith("format", "format: opencv"), "key 'format'");
  ExpectError(ExampleWith("version", "version: 2"), "key 'version': expected 1, got '2'");
  ExpectError(std::string(kExample) + "pich_deg: 3\n", "mount.yaml:9: unknown key 'pich_deg'");
  ExpectError("[1, 2, 3]\n", "expected a mapping");
  ExpectError("height_m: [1, 2\n", "YAML syntax error");
}

TEST(CameraMountYaml, FileErrorsNameTheFile) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("files");
  const std::filesystem::path missing = dir / "absent.yaml";
  const core::Result<CameraMount> absent = ReadCameraMountYaml(missing);
  ASSERT_FALSE(absent.ok());
  EXPECT_NE(absent.message().find(missing.string()), std::string::npos);

  const std::filesystem::path bad = dir / "bad.yaml";
  std::ofstream(bad) << ExampleWith("height_m", "height_m: -1");
  const core::Result<CameraMount> negative = ReadCameraMountYaml(bad);
  ASSERT_FALSE(negative.ok());
  EXPECT_NE(negative.message().find(bad.string() + ":3: key 'height_m'"), std::string::npos)
      << negative.message();

  CameraMount invalid;
  invalid.height_m = -1.0;
  const std::filesystem::path out = dir / "out.yaml";
  EXPECT_FALSE(WriteCameraMountYaml(invalid, out).ok());
  EXPECT_FALSE(std::filesystem::exists(out));
  // Like every writer it creates missing directories; a regular file where a
  // directory must be is an error, and nothing is left behind.
  std::ofstream(dir / "a_file") << "x";
  EXPECT_FALSE(WriteCameraMountYaml(CameraMount{}, dir / "a_file" / "out.yaml").ok());
  ASSERT_TRUE(WriteCameraMountYaml(CameraMount{}, dir / "new_dir" / "out.yaml").ok());
  EXPECT_TRUE(ReadCameraMountYaml(dir / "new_dir" / "out.yaml").ok());
  for (const auto& entry : std::filesystem::directory_iterator(dir / "new_dir")) {
    EXPECT_EQ(entry.path().filename(), "out.yaml") << "temporary file left behind";
  }
}

}  // namespace
}  // namespace groundline::calibration

namespace groundline::calibration {
namespace {

// The sample config shipped in samples/config is valid and is the reference AGV.
TEST(CameraMountYaml, SampleConfigIsTheReferenceVehicle) {
  const core::Result<CameraMount> mount = ReadCameraMountYaml(GROUNDLINE_SAMPLE_EXTRINSICS_FILE);
  ASSERT_TRUE(mount.ok()) << mount.message();
  EXPECT_DOUBLE_EQ(mount->height_m, 0.58);
  EXPECT_NEAR(mount->pitch_rad, 42.4 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(mount->forward_m, 0.42);
}

}  // namespace
}  // namespace groundline::calibration
