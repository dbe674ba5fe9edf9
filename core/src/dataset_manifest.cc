// Reading manifest.yaml into a DatasetManifest.
#include <filesystem>
#include <string>

#include "dataset_internal.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/text_parse.h"
#include "groundline/core/yaml_fields.h"

namespace groundline::core {
namespace {

using internal::YamlFields;

int AsInt(std::int64_t value) {
  // Out-of-range sizes become -1, which the checks report as invalid.
  return value >= 0 && value <= (1 << 30) ? static_cast<int>(value) : -1;
}

CameraSensor ParseCamera(YamlFields& y, const YAML::Node& node) {
  const std::string path = "sensors.camera";
  CameraSensor c;
  if (!y.ExpectMap(node, path)) return c;
  y.CheckKeys(
      node, path,
      {"image_width_px", "image_height_px", "rate_hz", "intrinsics_file", "extrinsics_file",
       "bev_uncertainty_file"});
  c.image_width_px = AsInt(y.Integer(node, path, "image_width_px"));
  c.image_height_px = AsInt(y.Integer(node, path, "image_height_px"));
  c.rate_hz = y.Number(node, path, "rate_hz");
  c.intrinsics_file = y.Text(node, path, "intrinsics_file");
  c.extrinsics_file = y.Text(node, path, "extrinsics_file");
  if (node["bev_uncertainty_file"]) {
    c.bev_uncertainty_file = y.Text(node, path, "bev_uncertainty_file");
  }
  return c;
}

WheelEncoderSensor ParseWheelEncoders(YamlFields& y, const YAML::Node& node) {
  const std::string path = "sensors.wheel_encoders";
  WheelEncoderSensor w;
  if (!y.ExpectMap(node, path)) return w;
  y.CheckKeys(node, path, {"rate_hz", "wheel_radius_m", "track_m", "ticks_per_rev"});
  w.rate_hz = y.Number(node, path, "rate_hz");
  w.wheel_radius_m = y.Number(node, path, "wheel_radius_m");
  w.track_m = y.Number(node, path, "track_m");
  w.ticks_per_rev = y.Integer(node, path, "ticks_per_rev");
  return w;
}

LidarSensor ParseLidar(YamlFields& y, const YAML::Node& node) {
  const std::string path = "sensors.lidar";
  LidarSensor l;
  if (!y.ExpectMap(node, path)) return l;
  y.CheckKeys(node, path,
              {"rate_hz", "T_base_lidar", "mount_height_m", "range_min_m", "range_max_m", "stamp"});
  l.rate_hz = y.Number(node, path, "rate_hz");
  const std::string pose_path = path + ".T_base_lidar";
  const YAML::Node pose = y.Child(node, path, "T_base_lidar");
  if (pose && y.ExpectMap(pose, pose_path)) {
    y.CheckKeys(pose, pose_path, {"x_m", "y_m", "yaw_rad"});
    const double x_m = y.Number(pose, pose_path, "x_m");
    const double y_m = y.Number(pose, pose_path, "y_m");
    const double yaw_rad = y.Number(pose, pose_path, "yaw_rad");
    l.T_base_lidar = SE2(x_m, y_m, yaw_rad);
  }
  l.mount_height_m = y.Number(node, path, "mount_height_m");
  l.range_min_m = y.Number(node, path, "range_min_m");
  l.range_max_m = y.Number(node, path, "range_max_m");
  if (node["stamp"]) {
    const std::string stamp = y.Text(node, path, "stamp");
    if (stamp == "first_ray") {
      l.stamp = LidarStamp::kFirstRay;
    } else if (stamp != "mid_sweep") {
      y.Fail(node["stamp"], path + ".stamp", "'mid_sweep' or 'first_ray'", stamp);
    }
  }
  return l;
}

// Files before 1.2 named the stamp convention only in the provenance of
// simulated datasets (lidar_stamp: mid_sweep; absent: the first ray).
void MigrateLidarStamp(const YAML::Node& lidar, DatasetManifest* m) {
  if (!m->lidar || lidar["stamp"]) return;
  const auto generator = m->provenance.find("generator");
  const auto stamp = m->provenance.find("lidar_stamp");
  if (generator != m->provenance.end() && generator->second == "groundline sim" &&
      (stamp == m->provenance.end() || stamp->second != "mid_sweep")) {
    m->lidar->stamp = LidarStamp::kFirstRay;
  }
}

std::optional<StartPose> ParseStartPose(YamlFields& y, const YAML::Node& root) {
  const YAML::Node node = y.Child(root, "", "start_pose", false);
  if (!node || !y.ExpectMap(node, "start_pose")) return std::nullopt;
  y.CheckKeys(node, "start_pose",
              {"stamp_s", "x_m", "y_m", "yaw_rad", "sigma_xy_m", "sigma_yaw_rad"});
  StartPose s;
  s.stamp_s = y.Number(node, "start_pose", "stamp_s");
  const double x_m = y.Number(node, "start_pose", "x_m");
  const double y_m = y.Number(node, "start_pose", "y_m");
  const double yaw_rad = y.Number(node, "start_pose", "yaw_rad");
  s.T_map_base = SE2(x_m, y_m, yaw_rad);
  if (node["sigma_xy_m"]) s.sigma_xy_m = y.Number(node, "start_pose", "sigma_xy_m");
  if (node["sigma_yaw_rad"]) s.sigma_yaw_rad = y.Number(node, "start_pose", "sigma_yaw_rad");
  return s;
}

void ParseSensors(YamlFields& y, const YAML::Node& root, DatasetManifest* m) {
  const YAML::Node sensors = y.Child(root, "", "sensors");
  if (!sensors || !y.ExpectMap(sensors, "sensors")) return;
  y.CheckKeys(sensors, "sensors", {"camera", "wheel_encoders", "lidar"});
  if (const YAML::Node n = y.Child(sensors, "sensors", "camera", false)) {
    m->camera = ParseCamera(y, n);
  }
  if (const YAML::Node n = y.Child(sensors, "sensors", "wheel_encoders", false)) {
    m->wheel_encoders = ParseWheelEncoders(y, n);
  }
  if (const YAML::Node n = y.Child(sensors, "sensors", "lidar", false)) {
    m->lidar = ParseLidar(y, n);
  }
}

void ParseFiles(YamlFields& y, const YAML::Node& root, DatasetFiles* files) {
  const YAML::Node node = y.Child(root, "", "files");
  if (!node || !y.ExpectMap(node, "files")) return;
  y.CheckKeys(node, "files",
              {"image_index", "wheel_encoders", "lidar_scans", "ground_truth", "floor_map",
               "ground_truth_extrinsics"});
  const std::pair<const char*, std::string*> entries[] = {
      {"image_index", &files->image_index},
      {"wheel_encoders", &files->wheel_encoders},
      {"lidar_scans", &files->lidar_scans},
      {"ground_truth", &files->ground_truth},
      {"floor_map", &files->floor_map},
      {"ground_truth_extrinsics", &files->ground_truth_extrinsics}};
  for (const auto& [key, target] : entries) {
    if (y.Child(node, "files", key, false)) *target = y.Text(node, "files", key);
  }
}

void ParseProvenance(YamlFields& y, const YAML::Node& root,
                     std::map<std::string, std::string>* provenance) {
  const YAML::Node node = y.Child(root, "", "provenance", false);
  if (!node || !y.ExpectMap(node, "provenance")) return;
  for (const auto& entry : node) {
    const std::string key = entry.first.Scalar();
    if (!entry.second.IsScalar() && !entry.second.IsNull()) {
      y.Fail(entry.second, internal::JoinPath("provenance", key), "a scalar value",
             "a nested value");
      return;
    }
    const std::string value = entry.second.IsNull() ? std::string() : entry.second.Scalar();
    if (!IsValidUtf8(key) || !IsValidUtf8(value)) {
      y.Fail(entry.second, internal::JoinPath("provenance", key), "UTF-8 text",
             "bytes that are not UTF-8");
      return;
    }
    (*provenance)[key] = value;
  }
}

// Every referenced file must exist relative to the manifest's directory.
void CheckReferencedFiles(YamlFields& y, const YAML::Node& root, const DatasetManifest& m,
                          const std::filesystem::path& dir) {
  std::vector<std::pair<std::string, std::string>> references;  // field path, file
  if (m.camera) {
    references.emplace_back("sensors.camera.intrinsics_file", m.camera->intrinsics_file);
    references.emplace_back("sensors.camera.extrinsics_file", m.camera->extrinsics_file);
    if (!m.camera->bev_uncertainty_file.empty()) {
      references.emplace_back("sensors.camera.bev_uncertainty_file",
                              m.camera->bev_uncertainty_file);
    }
  }
  const DatasetFiles& f = m.files;
  for (const auto& [key, file] :
       {std::pair<const char*, const std::string&>{"image_index", f.image_index},
        {"wheel_encoders", f.wheel_encoders},
        {"lidar_scans", f.lidar_scans},
        {"ground_truth", f.ground_truth},
        {"floor_map", f.floor_map},
        {"ground_truth_extrinsics", f.ground_truth_extrinsics}}) {
    if (!file.empty()) references.emplace_back(std::string("files.") + key, file);
  }
  for (const auto& [field, file] : references) {
    if (std::filesystem::is_regular_file(dir / file)) continue;
    y.Fail(internal::LineOfPath(root, field), field,
           "a file that exists in " + dir.string() + " (the referenced file is missing)", file);
    return;
  }
}

}  // namespace

namespace {

Result<DatasetManifest> ReadDatasetManifestUnguarded(const std::filesystem::path& path) {
  Result<YAML::Node> loaded = internal::LoadYamlFile(path);
  if (!loaded.ok()) return loaded.status();
  const YAML::Node& root = *loaded;
  YamlFields y(path.string());
  DatasetManifest m;
  y.CheckFormat(root, kDatasetFormatName, kDatasetFormatMajor, kDatasetFormatMinor,
                &m.version_major, &m.version_minor);
  if (!y.ok()) return y.status();
  y.CheckKeys(root, "",
              {"format", "version", "name", "description", "units", "frames", "sensors", "files",
               "provenance", "start_pose"});
  m.name = y.Text(root, "", "name");
  m.description = y.Text(root, "", "description", /*allow_empty=*/true);
  if (const std::string units = y.Text(root, "", "units"); y.ok() && units != "SI") {
    y.Fail(root["units"], "units", "'SI' (m, rad, s, Hz)", units);
  }
  const YAML::Node frames = y.Child(root, "", "frames");
  if (frames && y.ExpectMap(frames, "frames")) {
    y.CheckKeys(frames, "frames", {"map", "odom", "base_link"});
    m.frames.map = y.Text(frames, "frames", "map");
    m.frames.odom = y.Text(frames, "frames", "odom");
    m.frames.base_link = y.Text(frames, "frames", "base_link");
  }
  ParseSensors(y, root, &m);
  ParseFiles(y, root, &m.files);
  ParseProvenance(y, root, &m.provenance);
  m.start_pose = ParseStartPose(y, root);
  if (!y.ok()) return y.status();
  if (const YAML::Node sensors = root["sensors"]; sensors && sensors.IsMap()) {
    MigrateLidarStamp(sensors["lidar"], &m);
  }
  if (const std::optional<internal::FieldProblem> problem = internal::CheckManifest(m)) {
    y.Fail(internal::LineOfPath(root, problem->field), problem->field, problem->expected,
           problem->got);
    return y.status();
  }
  CheckReferencedFiles(y, root, m, path.has_parent_path() ? path.parent_path() : ".");
  if (!y.ok()) return y.status();
  return m;
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
Result<DatasetManifest> ReadDatasetManifest(const std::filesystem::path& path) {
  return internal::CatchYamlErrors(path.string(),
                                   [&] { return ReadDatasetManifestUnguarded(path); });
}

Status WriteDatasetManifest(const std::filesystem::path& path, const DatasetManifest& manifest) {
  if (Status s = manifest.Validate(); !s.ok()) return s.WithContext(path.string());
  return WriteFileAtomically(path, internal::FormatManifest(manifest));
}

}  // namespace groundline::core
