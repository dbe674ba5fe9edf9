// The rules of manifest.yaml (docs/dataset.md), on the value type.
#include <cmath>
#include <string>

#include "dataset_internal.h"
#include "text_lines.h"

namespace groundline::core::internal {
namespace {

using Problem = std::optional<FieldProblem>;

std::string Str(double value) { return FormatShortest(value); }

Problem Positive(const std::string& field, double value) {
  if (std::isfinite(value) && value > 0.0) return std::nullopt;
  return FieldProblem{field, "a finite number > 0", Str(value)};
}

// A sensor rate beyond these is a unit mistake (a period or kHz written as
// Hz) or a typo, not a sensor: cameras and planar LiDARs run at up to a few
// hundred Hz, wheel encoders are read at up to a few kHz.
constexpr double kMaxCameraRateHz = 1000.0;
constexpr double kMaxLidarRateHz = 1000.0;
constexpr double kMaxWheelRateHz = 10000.0;
// A planar LiDAR on a vehicle, metres.
constexpr double kMaxLidarMountHeightM = 5.0;

Problem Rate(const std::string& field, double value, double max_hz) {
  if (std::isfinite(value) && value > 0.0 && value <= max_hz) return std::nullopt;
  return FieldProblem{field, "a rate in (0, " + Str(max_hz) + "] Hz", Str(value)};
}

Problem Finite(const std::string& field, double value) {
  if (std::isfinite(value)) return std::nullopt;
  return FieldProblem{field, "a finite number", Str(value)};
}

Problem RelativePath(const std::string& field, const std::string& path) {
  const std::string problem = RelativePathProblem(path);
  if (problem.empty()) return std::nullopt;
  return FieldProblem{field, problem, path};
}

Problem CheckCamera(const CameraSensor& c) {
  const std::string p = "sensors.camera.";
  if (c.image_width_px <= 0) {
    return FieldProblem{p + "image_width_px", "a width > 0", std::to_string(c.image_width_px)};
  }
  if (c.image_height_px <= 0) {
    return FieldProblem{p + "image_height_px", "a height > 0", std::to_string(c.image_height_px)};
  }
  if (Problem e = Rate(p + "rate_hz", c.rate_hz, kMaxCameraRateHz)) return e;
  if (Problem e = RelativePath(p + "intrinsics_file", c.intrinsics_file)) return e;
  if (!c.bev_uncertainty_file.empty()) {
    if (Problem e = RelativePath(p + "bev_uncertainty_file", c.bev_uncertainty_file)) return e;
  }
  return RelativePath(p + "extrinsics_file", c.extrinsics_file);
}

Problem CheckWheelEncoders(const WheelEncoderSensor& w) {
  const std::string p = "sensors.wheel_encoders.";
  if (Problem e = Rate(p + "rate_hz", w.rate_hz, kMaxWheelRateHz)) return e;
  if (Problem e = Positive(p + "wheel_radius_m", w.wheel_radius_m)) return e;
  if (Problem e = Positive(p + "track_m", w.track_m)) return e;
  if (w.ticks_per_rev <= 0) {
    return FieldProblem{p + "ticks_per_rev", "a count > 0", std::to_string(w.ticks_per_rev)};
  }
  return std::nullopt;
}

Problem CheckLidar(const LidarSensor& l) {
  const std::string p = "sensors.lidar.";
  if (Problem e = Rate(p + "rate_hz", l.rate_hz, kMaxLidarRateHz)) return e;
  if (Problem e = Finite(p + "T_base_lidar.x_m", l.T_base_lidar.x())) return e;
  if (Problem e = Finite(p + "T_base_lidar.y_m", l.T_base_lidar.y())) return e;
  if (Problem e = Finite(p + "T_base_lidar.yaw_rad", l.T_base_lidar.yaw())) return e;
  if (!(std::isfinite(l.mount_height_m) && l.mount_height_m >= 0.0 &&
        l.mount_height_m <= kMaxLidarMountHeightM)) {
    return FieldProblem{p + "mount_height_m", "a height in [0, 5] m (metres, not mm or cm)",
                        Str(l.mount_height_m)};
  }
  if (!(std::isfinite(l.range_min_m) && l.range_min_m >= kMinRangeLimit_m)) {
    return FieldProblem{p + "range_min_m", "a finite limit >= 0.001 (0 encodes 'no return')",
                        Str(l.range_min_m)};
  }
  if (!(std::isfinite(l.range_max_m) && l.range_max_m > l.range_min_m)) {
    return FieldProblem{p + "range_max_m", "a finite limit > range_min_m", Str(l.range_max_m)};
  }
  return std::nullopt;
}

// A sensor is present iff its stream file is listed.
Problem CheckPairing(bool has_sensor, const char* sensor, const std::string& file,
                     const char* key) {
  const std::string field = std::string("files.") + key;
  if (has_sensor && file.empty()) {
    return FieldProblem{field, std::string("a file, since sensors.") + sensor + " is present", ""};
  }
  if (!has_sensor && !file.empty()) {
    return FieldProblem{field, std::string("no file, since sensors.") + sensor + " is absent",
                        file};
  }
  return file.empty() ? std::nullopt : RelativePath(field, file);
}

}  // namespace

std::optional<FieldProblem> CheckManifest(const DatasetManifest& m) {
  if (m.name.empty()) return FieldProblem{"name", "a non-empty dataset name", ""};
  const DatasetFrames& f = m.frames;
  if (f.map.empty()) return FieldProblem{"frames.map", "a non-empty frame name", ""};
  if (f.odom.empty() || f.odom == f.map) {
    return FieldProblem{"frames.odom", "a non-empty name other than frames.map", f.odom};
  }
  if (f.base_link.empty() || f.base_link == f.map || f.base_link == f.odom) {
    return FieldProblem{"frames.base_link", "a non-empty name other than map and odom",
                        f.base_link};
  }
  if (m.camera) {
    if (Problem e = CheckCamera(*m.camera)) return e;
  }
  if (m.wheel_encoders) {
    if (Problem e = CheckWheelEncoders(*m.wheel_encoders)) return e;
  }
  if (m.lidar) {
    if (Problem e = CheckLidar(*m.lidar)) return e;
  }
  if (m.start_pose) {
    const StartPose& s = *m.start_pose;
    if (Problem e = Finite("start_pose.stamp_s", s.stamp_s)) return e;
    if (Problem e = Finite("start_pose.x_m", s.T_map_base.x())) return e;
    if (Problem e = Finite("start_pose.y_m", s.T_map_base.y())) return e;
    if (Problem e = Finite("start_pose.yaw_rad", s.T_map_base.yaw())) return e;
    if (Problem e = Positive("start_pose.sigma_xy_m", s.sigma_xy_m)) return e;
    if (Problem e = Positive("start_pose.sigma_yaw_rad", s.sigma_yaw_rad)) return e;
  }
  const DatasetFiles& files = m.files;
  if (Problem e = CheckPairing(m.camera.has_value(), "camera", files.image_index, "image_index")) {
    return e;
  }
  if (Problem e = CheckPairing(m.wheel_encoders.has_value(), "wheel_encoders", files.wheel_encoders,
                               "wheel_encoders")) {
    return e;
  }
  if (Problem e = CheckPairing(m.lidar.has_value(), "lidar", files.lidar_scans, "lidar_scans")) {
    return e;
  }
  if (!files.ground_truth.empty()) {
    if (Problem e = RelativePath("files.ground_truth", files.ground_truth)) return e;
  }
  if (!files.floor_map.empty()) {
    if (Problem e = RelativePath("files.floor_map", files.floor_map)) return e;
  }
  if (!files.ground_truth_extrinsics.empty()) {
    if (Problem e = RelativePath("files.ground_truth_extrinsics", files.ground_truth_extrinsics)) {
      return e;
    }
    if (!m.camera) {
      return FieldProblem{"files.ground_truth_extrinsics",
                          "no ground-truth extrinsics without a sensors.camera",
                          files.ground_truth_extrinsics};
    }
  }
  const std::pair<const char*, const std::string*> listed[] = {
      {"image_index", &files.image_index},
      {"wheel_encoders", &files.wheel_encoders},
      {"lidar_scans", &files.lidar_scans},
      {"ground_truth", &files.ground_truth},
      {"floor_map", &files.floor_map},
      {"ground_truth_extrinsics", &files.ground_truth_extrinsics}};
  for (std::size_t i = 0; i < std::size(listed); ++i) {
    const std::string& file = *listed[i].second;
    if (file == kManifestFileName) {
      return FieldProblem{std::string("files.") + listed[i].first,
                          "a name other than the manifest's", file};
    }
    for (std::size_t j = 0; j < i && !file.empty(); ++j) {
      if (file == *listed[j].second) {
        return FieldProblem{std::string("files.") + listed[i].first,
                            std::string("a file other than files.") + listed[j].first, file};
      }
    }
  }
  for (const auto& [key, value] : m.provenance) {
    if (key.empty()) return FieldProblem{"provenance", "non-empty keys", value};
  }
  return std::nullopt;
}

Status ProblemStatus(const std::string& label, const FieldProblem& problem) {
  return Status::Error(label + ": field '" + problem.field + "': expected " + problem.expected +
                       ", got '" + problem.got + "'");
}

}  // namespace groundline::core::internal

namespace groundline::core {

Status DatasetManifest::Validate() const {
  if (const auto problem = internal::CheckManifest(*this)) {
    return internal::ProblemStatus("dataset manifest", *problem);
  }
  return Status::Ok();
}

}  // namespace groundline::core
