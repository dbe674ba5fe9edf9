#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/core/yaml_fields.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <system_error>

#include "groundline/core/atomic_file.h"
#include "groundline/core/text_parse.h"
#include "yaml_text.h"

namespace groundline::calibration {
namespace {

constexpr double kMaxMountHeightM = 5.0;
constexpr double kMaxMountOffsetM = 10.0;

double DegToRad(double deg) {
  // Keeps +-180 deg at exactly +-pi so that it passes CameraMount::Validate().
  return std::clamp(deg * std::numbers::pi / 180.0, -std::numbers::pi, std::numbers::pi);
}
double RadToDeg(double rad) { return rad * 180.0 / std::numbers::pi; }

std::string Where(const std::string& source, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.is_null()) return source;
  return source + ":" + std::to_string(mark.line + 1);
}

std::string Describe(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  return "nothing";
}

struct KeySpec {
  const char* key;
  const char* meaning;  // for "missing key" messages
};

constexpr std::array<KeySpec, 8> kKeys = {{
    {"format", "the string groundline_camera_extrinsics"},
    {"version", "the format version, 1"},
    {"height_m", "optical centre height above the floor, metres"},
    {"pitch_deg", "downward tilt of the optical axis, degrees"},
    {"roll_deg", "roll about the optical axis, degrees"},
    {"yaw_deg", "yaw about the vertical, left positive, degrees"},
    {"forward_m", "optical centre ahead of base_link, metres"},
    {"lateral_m", "optical centre left of base_link, metres"},
}};

// Reads map[key] as a finite number.
core::Result<double> ReadNumber(const YAML::Node& map, const std::string& source,
                                const std::string& key) {
  const YAML::Node node = map[key];
  double value = 0.0;
  bool parsed = node.IsScalar();
  if (parsed) {
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      parsed = false;
    }
  }
  if (!parsed || !std::isfinite(value)) {
    return core::Status::Error(Where(source, node) + ": key '" + key +
                               "': expected a finite number, got " + Describe(node));
  }
  return value;
}

core::Status RangeError(const std::string& source, const YAML::Node& node, const std::string& key,
                        const std::string& expected) {
  return core::Status::Error(Where(source, node) + ": key '" + key + "': expected " + expected +
                             ", got " + node.Scalar());
}

}  // namespace

namespace {

core::Result<CameraMount> ParseCameraMountYamlUnguarded(const std::string& yaml_text,
                                                        const std::string& source_name) {
  const core::Result<YAML::Node> loaded = internal::LoadYamlText(yaml_text, source_name);
  if (!loaded.ok()) return loaded.status();
  const YAML::Node& root = *loaded;  // const: lookups of absent keys must not insert them
  if (!root.IsMap()) {
    return core::Status::Error(source_name +
                               ": expected a mapping of camera extrinsics keys at the top level");
  }
  for (const auto& entry : root) {
    const std::string key = entry.first.Scalar();
    bool known = false;
    for (const KeySpec& spec : kKeys) known = known || key == spec.key;
    if (!known) {
      return core::Status::Error(Where(source_name, entry.first) + ": unknown key '" + key +
                                 "' (see docs/extrinsics.md for the keys)");
    }
  }
  for (const KeySpec& spec : kKeys) {
    if (!root[spec.key]) {
      return core::Status::Error(source_name + ": missing key '" + spec.key + "' (" + spec.meaning +
                                 ")");
    }
  }
  const YAML::Node format = root["format"];
  if (!format.IsScalar() || format.Scalar() != kCameraMountFormat) {
    return core::Status::Error(Where(source_name, format) + ": key 'format': expected '" +
                               kCameraMountFormat + "', got " + Describe(format));
  }
  const YAML::Node version = root["version"];
  if (!version.IsScalar() || version.Scalar() != std::to_string(kCameraMountVersion)) {
    return core::Status::Error(Where(source_name, version) + ": key 'version': expected " +
                               std::to_string(kCameraMountVersion) + ", got " + Describe(version));
  }

  std::array<double, 6> values{};
  constexpr std::array<const char*, 6> kNumberKeys = {"height_m", "pitch_deg", "roll_deg",
                                                      "yaw_deg",  "forward_m", "lateral_m"};
  for (size_t i = 0; i < kNumberKeys.size(); ++i) {
    core::Result<double> value = ReadNumber(root, source_name, kNumberKeys[i]);
    if (!value.ok()) return value.status();
    values[i] = *value;
  }
  const auto& [height_m, pitch_deg, roll_deg, yaw_deg, forward_m, lateral_m] = values;
  // A camera on a vehicle: a height or offset beyond these is a unit mistake
  // (mm or cm written as m) or a typo, not a mount.
  if (!(height_m > 0.0 && height_m <= kMaxMountHeightM)) {
    return RangeError(source_name, root["height_m"], "height_m",
                      "a height above the floor in (0, 5] m (metres, not mm or cm)");
  }
  if (std::abs(forward_m) > kMaxMountOffsetM) {
    return RangeError(source_name, root["forward_m"], "forward_m",
                      "an offset ahead of base_link in [-10, 10] m (metres, not mm or cm)");
  }
  if (std::abs(lateral_m) > kMaxMountOffsetM) {
    return RangeError(source_name, root["lateral_m"], "lateral_m",
                      "an offset left of base_link in [-10, 10] m (metres, not mm or cm)");
  }
  if (std::abs(pitch_deg) >= 90.0) {
    return RangeError(source_name, root["pitch_deg"], "pitch_deg", "|pitch| < 90");
  }
  if (std::abs(roll_deg) > 180.0) {
    return RangeError(source_name, root["roll_deg"], "roll_deg", "an angle in [-180, 180]");
  }
  if (std::abs(yaw_deg) > 180.0) {
    return RangeError(source_name, root["yaw_deg"], "yaw_deg", "an angle in [-180, 180]");
  }

  CameraMount mount;
  mount.height_m = height_m;
  mount.pitch_rad = DegToRad(pitch_deg);
  mount.roll_rad = DegToRad(roll_deg);
  mount.yaw_rad = DegToRad(yaw_deg);
  mount.forward_m = forward_m;
  mount.lateral_m = lateral_m;
  if (core::Status status = mount.Validate(); !status.ok()) {
    return status.WithContext(source_name);
  }
  return mount;
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
core::Result<CameraMount> ParseCameraMountYaml(const std::string& yaml_text,
                                               const std::string& source_name) {
  return core::internal::CatchYamlErrors(
      source_name, [&] { return ParseCameraMountYamlUnguarded(yaml_text, source_name); });
}

core::Result<CameraMount> ReadCameraMountYaml(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return core::Status::Error(path.string() +
                               ": cannot open the camera extrinsics file for reading");
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return core::Status::Error(path.string() + ": read error");
  return ParseCameraMountYaml(text.str(), path.string());
}

std::string CameraMountToYaml(const CameraMount& mount) {
  assert(mount.Validate().ok());
  std::ostringstream out;
  out << "# groundline camera extrinsics: pose of the camera optical frame in base_link.\n"
      << "# Lengths in metres, angles in degrees; see docs/extrinsics.md.\n"
      << "format: " << kCameraMountFormat << "\n"
      << "version: " << kCameraMountVersion << "\n"
      << "height_m: " << core::FormatYamlDouble(mount.height_m) << "\n"
      << "pitch_deg: " << core::FormatYamlDouble(RadToDeg(mount.pitch_rad)) << "\n"
      << "roll_deg: " << core::FormatYamlDouble(RadToDeg(mount.roll_rad)) << "\n"
      << "yaw_deg: " << core::FormatYamlDouble(RadToDeg(mount.yaw_rad)) << "\n"
      << "forward_m: " << core::FormatYamlDouble(mount.forward_m) << "\n"
      << "lateral_m: " << core::FormatYamlDouble(mount.lateral_m) << "\n";
  return out.str();
}

core::Status WriteCameraMountYaml(const CameraMount& mount, const std::filesystem::path& path) {
  if (core::Status status = mount.Validate(); !status.ok()) {
    return status.WithContext(path.string() + ": refusing to write an invalid camera mount");
  }
  return core::WriteFileAtomically(path, CameraMountToYaml(mount))
      .WithContext(path.string() + ": cannot write the camera extrinsics file");
}

}  // namespace groundline::calibration
