// Formatting manifest.yaml and floor_map.yaml. Numbers are emitted as their
// shortest exact text (std::to_chars), so they read back to the same double
// and do not depend on the locale; free text is double-quoted.
#include <string>

#include <yaml-cpp/yaml.h>

#include "dataset_internal.h"
#include "groundline/core/text_parse.h"
#include "text_lines.h"

namespace groundline::core::internal {
namespace {

constexpr char kManifestHeader[] =
    "# groundline dataset manifest (format: docs/dataset.md).\n"
    "# Units: SI (m, rad, s, Hz); every key with a unit names it (rate_hz, x_m, yaw_rad).\n"
    "# Frames (REP-105): map -> odom -> base_link; T_a_b maps points from b into a.\n"
    "# Stamps in every file: float64 seconds, one clock for all sensors.\n";

constexpr char kFloorMapHeader[] =
    "# groundline floor map: ground-truth floor markings (format: docs/dataset.md).\n"
    "# polyline_m: centre line in the map frame, metres; width_m across it.\n"
    "# colour_rgb: 8-bit sRGB; polarity: bright or dark against the floor.\n"
    "# dash_m/gap_m (tape_dashed only): the pattern starts with a dash at the first vertex.\n"
    "# survey (optional): the survey's stated 1-sigma accuracy.\n";

std::string Version(int major, int minor) {
  return std::to_string(major) + "." + std::to_string(minor);
}

void Number(YAML::Emitter& out, const char* key, double value) {
  out << YAML::Key << key << YAML::Value << FormatYamlDouble(value);
}

void Quoted(YAML::Emitter& out, const char* key, const std::string& value) {
  out << YAML::Key << key << YAML::Value << YAML::DoubleQuoted << value;
}

void EmitSensors(YAML::Emitter& out, const DatasetManifest& m) {
  out << YAML::Key << "sensors" << YAML::Value;
  // Flow style for an empty mapping: "sensors: {}" rather than "{}" on its own line.
  if (!m.camera && !m.wheel_encoders && !m.lidar) out << YAML::Flow;
  out << YAML::BeginMap;
  if (m.camera) {
    const CameraSensor& c = *m.camera;
    out << YAML::Key << "camera" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "image_width_px" << YAML::Value << c.image_width_px;
    out << YAML::Key << "image_height_px" << YAML::Value << c.image_height_px;
    Number(out, "rate_hz", c.rate_hz);
    Quoted(out, "intrinsics_file", c.intrinsics_file);
    Quoted(out, "extrinsics_file", c.extrinsics_file);
    if (!c.bev_uncertainty_file.empty()) {
      Quoted(out, "bev_uncertainty_file", c.bev_uncertainty_file);
    }
    out << YAML::EndMap;
  }
  if (m.wheel_encoders) {
    const WheelEncoderSensor& w = *m.wheel_encoders;
    out << YAML::Key << "wheel_encoders" << YAML::Value << YAML::BeginMap;
    Number(out, "rate_hz", w.rate_hz);
    Number(out, "wheel_radius_m", w.wheel_radius_m);
    Number(out, "track_m", w.track_m);
    out << YAML::Key << "ticks_per_rev" << YAML::Value << w.ticks_per_rev;
    out << YAML::EndMap;
  }
  if (m.lidar) {
    const LidarSensor& l = *m.lidar;
    out << YAML::Key << "lidar" << YAML::Value << YAML::BeginMap;
    Number(out, "rate_hz", l.rate_hz);
    out << YAML::Key << "T_base_lidar" << YAML::Value << YAML::Flow << YAML::BeginMap;
    Number(out, "x_m", l.T_base_lidar.x());
    Number(out, "y_m", l.T_base_lidar.y());
    Number(out, "yaw_rad", l.T_base_lidar.yaw());
    out << YAML::EndMap;
    Number(out, "mount_height_m", l.mount_height_m);
    Number(out, "range_min_m", l.range_min_m);
    Number(out, "range_max_m", l.range_max_m);
    Quoted(out, "stamp", l.stamp == LidarStamp::kFirstRay ? "first_ray" : "mid_sweep");
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

void EmitFiles(YAML::Emitter& out, const DatasetFiles& f) {
  out << YAML::Key << "files" << YAML::Value << YAML::BeginMap;
  const std::pair<const char*, const std::string*> entries[] = {
      {"image_index", &f.image_index}, {"wheel_encoders", &f.wheel_encoders},
      {"lidar_scans", &f.lidar_scans}, {"ground_truth", &f.ground_truth},
      {"floor_map", &f.floor_map},     {"ground_truth_extrinsics", &f.ground_truth_extrinsics}};
  for (const auto& [key, value] : entries) {
    if (!value->empty()) Quoted(out, key, *value);
  }
  out << YAML::EndMap;
}

void EmitMarking(YAML::Emitter& out, const FloorMarking& marking) {
  out << YAML::BeginMap;
  out << YAML::Key << "id" << YAML::Value << marking.id;
  out << YAML::Key << "kind" << YAML::Value << std::string(MarkingKindName(marking.kind));
  Number(out, "width_m", marking.width_m);
  out << YAML::Key << "colour_rgb" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << marking.colour_rgb[0] << marking.colour_rgb[1] << marking.colour_rgb[2] << YAML::EndSeq;
  out << YAML::Key << "polarity" << YAML::Value
      << (marking.polarity == MarkingPolarity::kBright ? "bright" : "dark");
  out << YAML::Key << "polyline_m" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const Vector2& p : marking.polyline_m) {
    out << YAML::Flow << YAML::BeginSeq << FormatYamlDouble(p.x()) << FormatYamlDouble(p.y())
        << YAML::EndSeq;
  }
  out << YAML::EndSeq;
  if (marking.dash_m) Number(out, "dash_m", *marking.dash_m);
  if (marking.gap_m) Number(out, "gap_m", *marking.gap_m);
  out << YAML::EndMap;
}

}  // namespace

std::string FormatManifest(const DatasetManifest& m) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << kDatasetFormatName;
  out << YAML::Key << "version" << YAML::Value << Version(kDatasetFormatMajor, kDatasetFormatMinor);
  Quoted(out, "name", m.name);
  Quoted(out, "description", m.description);
  out << YAML::Key << "units" << YAML::Value << "SI";
  out << YAML::Key << "frames" << YAML::Value << YAML::BeginMap;
  Quoted(out, "map", m.frames.map);
  Quoted(out, "odom", m.frames.odom);
  Quoted(out, "base_link", m.frames.base_link);
  out << YAML::EndMap;
  EmitSensors(out, m);
  if (m.start_pose) {
    const StartPose& s = *m.start_pose;
    out << YAML::Key << "start_pose" << YAML::Value << YAML::Flow << YAML::BeginMap;
    Number(out, "stamp_s", s.stamp_s);
    Number(out, "x_m", s.T_map_base.x());
    Number(out, "y_m", s.T_map_base.y());
    Number(out, "yaw_rad", s.T_map_base.yaw());
    Number(out, "sigma_xy_m", s.sigma_xy_m);
    Number(out, "sigma_yaw_rad", s.sigma_yaw_rad);
    out << YAML::EndMap;
  }
  EmitFiles(out, m.files);
  out << YAML::Key << "provenance" << YAML::Value;
  if (m.provenance.empty()) out << YAML::Flow;
  out << YAML::BeginMap;
  for (const auto& [key, value] : m.provenance) {
    out << YAML::Key << YAML::DoubleQuoted << key << YAML::Value << YAML::DoubleQuoted << value;
  }
  out << YAML::EndMap;
  out << YAML::EndMap;
  return std::string(kManifestHeader) + out.c_str() + "\n";
}

std::string FormatFloorMap(const FloorMap& map) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << kFloorMapFormatName;
  out << YAML::Key << "version" << YAML::Value
      << Version(kFloorMapFormatMajor, kFloorMapFormatMinor);
  Quoted(out, "frame", map.frame);
  if (map.survey) {
    out << YAML::Key << "survey" << YAML::Value << YAML::BeginMap;
    Number(out, "marking_vertex_sigma_m", map.survey->marking_vertex_sigma_m);
    Number(out, "face_offset_sigma_m", map.survey->face_offset_sigma_m);
    Number(out, "face_angle_sigma_rad", map.survey->face_angle_sigma_rad);
    out << YAML::EndMap;
  }
  out << YAML::Key << "markings" << YAML::Value;
  if (map.markings.empty()) out << YAML::Flow;
  out << YAML::BeginSeq;
  for (const FloorMarking& marking : map.markings) EmitMarking(out, marking);
  out << YAML::EndSeq;
  out << YAML::EndMap;
  return std::string(kFloorMapHeader) + out.c_str() + "\n";
}

}  // namespace groundline::core::internal
