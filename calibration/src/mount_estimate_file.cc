#include "groundline/calibration/mount_estimate_file.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "groundline/core/angles.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/covariance.h"
#include "groundline/core/json_fields.h"

namespace groundline::calibration {
namespace {

constexpr const char* kFormat = "groundline-mount-estimate";
constexpr int kVersion = 1;

nlohmann::ordered_json MountJson(const CameraMount& m) {
  return {{"pitch_deg", m.pitch_rad * core::kRadToDeg}, {"roll_deg", m.roll_rad * core::kRadToDeg},
          {"height_m", m.height_m},                     {"yaw_deg", m.yaw_rad * core::kRadToDeg},
          {"forward_m", m.forward_m},                   {"lateral_m", m.lateral_m}};
}

CameraMount ReadMount(core::JsonFieldReader& reader, const nlohmann::json& root, const char* key) {
  CameraMount m;
  const nlohmann::json* j = reader.Get(root, "", key);
  if (!j) return m;
  const std::string path = std::string(key) + ".";
  m.pitch_rad = reader.Finite(*j, path, "pitch_deg") * core::kDegToRad;
  m.roll_rad = reader.Finite(*j, path, "roll_deg") * core::kDegToRad;
  m.height_m = reader.Finite(*j, path, "height_m");
  m.yaw_rad = reader.Finite(*j, path, "yaw_deg") * core::kDegToRad;
  m.forward_m = reader.Finite(*j, path, "forward_m");
  m.lateral_m = reader.Finite(*j, path, "lateral_m");
  return m;
}

}  // namespace

core::Status WriteMountEstimate(const std::filesystem::path& path, const SavedMountEstimate& s) {
  const MountEstimate& e = s.estimate;
  nlohmann::ordered_json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["commissioned"] = MountJson(s.commissioned);
  j["estimate"] = MountJson(e.mount);
  j["covariance"] = nlohmann::ordered_json::array();
  for (int i = 0; i < 16; ++i) j["covariance"].push_back(e.covariance(i / 4, i % 4));
  j["alarm"] = e.alarm;
  j["alarm_message"] = e.alarm_message;
  j["frames"] = e.frames;
  j["windows_used"] = e.windows_used;
  j["steps"] = e.steps;
  j["last_update_s"] = e.last_update_s;
  return core::WriteFileAtomically(path, j.dump(2) + "\n");
}

core::Result<SavedMountEstimate> ReadMountEstimate(const std::filesystem::path& path) {
  nlohmann::json root;
  if (core::Status s = core::ReadJsonFile(path, "saved mount estimate", &root); !s.ok()) return s;
  core::JsonFieldReader reader(path.string());
  const std::string format = reader.String(root, "", "format");
  const double version = reader.Number(root, "", "version");
  if (format != kFormat) reader.Fail("format", std::string("\"") + kFormat + "\"", "\"" + format + "\"");
  if (version != kVersion) reader.Fail("version", std::to_string(kVersion), std::to_string(version));
  SavedMountEstimate s;
  s.commissioned = ReadMount(reader, root, "commissioned");
  s.estimate.mount = ReadMount(reader, root, "estimate");
  const std::vector<double> cov = reader.Numbers(root, "", "covariance", 16);
  const nlohmann::json* alarm = reader.Get(root, "", "alarm");
  if (alarm && !alarm->is_boolean()) reader.Fail("alarm", "true or false", alarm->dump());
  s.estimate.alarm_message = reader.String(root, "", "alarm_message");
  s.estimate.frames = static_cast<int>(reader.Id(root, "", "frames"));
  s.estimate.windows_used = static_cast<int>(reader.Id(root, "", "windows_used"));
  s.estimate.steps = static_cast<int>(reader.Id(root, "", "steps"));
  s.estimate.last_update_s = reader.Finite(root, "", "last_update_s");
  if (!reader.ok()) return reader.status();
  s.estimate.alarm = alarm->get<bool>();
  for (const auto& [which, mount] :
       {std::pair{"commissioned", &s.commissioned}, std::pair{"estimate", &s.estimate.mount}}) {
    if (core::Status v = mount->Validate(); !v.ok()) {
      return core::Status::Error(path.string() + ": field '" + which + "': " + v.message());
    }
  }
  for (int i = 0; i < 16; ++i) s.estimate.covariance(i / 4, i % 4) = cov[i];
  if (!core::IsCovariance(s.estimate.covariance)) {
    return core::Status::Error(path.string() +
                               ": field 'covariance': expected a symmetric positive definite 4x4 "
                               "covariance (16 numbers, row-major over pitch, roll, height, yaw)");
  }
  return s;
}

}  // namespace groundline::calibration
