// floor_map.yaml: the ground-truth floor markings.
#include "groundline/core/floor_map.h"

#include <cmath>
#include <set>
#include <string>

#include "dataset_internal.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/yaml_fields.h"
#include "text_lines.h"

namespace groundline::core {
namespace {

using internal::FieldProblem;
using internal::YamlFields;

constexpr std::pair<MarkingKind, std::string_view> kKindNames[] = {
    {MarkingKind::kTapeSolid, "tape_solid"},
    {MarkingKind::kTapeDashed, "tape_dashed"},
    {MarkingKind::kStopBar, "stop_bar"},
    {MarkingKind::kCrosswalkStripe, "crosswalk_stripe"},
    {MarkingKind::kStagingBoxEdge, "staging_box_edge"},
    {MarkingKind::kJoint, "joint"},
    {MarkingKind::kWall, "wall"},
    {MarkingKind::kRackFace, "rack_face"}};
constexpr double kMinVertexSpacing_m = 1e-3;

std::optional<FieldProblem> CheckMarking(const FloorMarking& m, const std::string& p) {
  using internal::FormatShortest;
  if (m.id < 0) return FieldProblem{p + ".id", "an id >= 0", std::to_string(m.id)};
  if (!(std::isfinite(m.width_m) && m.width_m > 0.0)) {
    return FieldProblem{p + ".width_m", "a finite width > 0", FormatShortest(m.width_m)};
  }
  for (int c : m.colour_rgb) {
    if (c < 0 || c > 255) {
      return FieldProblem{p + ".colour_rgb", "three 8-bit values in [0, 255]", std::to_string(c)};
    }
  }
  if (m.polyline_m.size() < 2) {
    return FieldProblem{p + ".polyline_m", "at least 2 vertices",
                        std::to_string(m.polyline_m.size()) + " vertices"};
  }
  for (std::size_t j = 0; j < m.polyline_m.size(); ++j) {
    const std::string field = internal::IndexPath(p + ".polyline_m", j);
    const Vector2& v = m.polyline_m[j];
    if (!v.allFinite()) return FieldProblem{field, "finite coordinates", "non-finite"};
    if (j > 0 && (v - m.polyline_m[j - 1]).norm() < kMinVertexSpacing_m) {
      return FieldProblem{field, "a vertex >= 1 mm from the previous one",
                          FormatShortest(v.x()) + ", " + FormatShortest(v.y())};
    }
  }
  const bool dashed = m.kind == MarkingKind::kTapeDashed;
  for (const auto& [name, value] : {std::pair{"dash_m", m.dash_m}, std::pair{"gap_m", m.gap_m}}) {
    const std::string field = p + "." + name;
    if (dashed && !value) return FieldProblem{field, "a length for a tape_dashed marking", ""};
    if (!dashed && value) {
      return FieldProblem{field, "no dash pattern on a non-dashed marking", FormatShortest(*value)};
    }
    if (value && !(std::isfinite(*value) && *value > 0.0)) {
      return FieldProblem{field, "a finite length > 0", FormatShortest(*value)};
    }
  }
  return std::nullopt;
}

FloorMarking ParseMarking(YamlFields& y, const YAML::Node& node, const std::string& p) {
  FloorMarking m;
  if (!y.ExpectMap(node, p)) return m;
  y.CheckKeys(node, p,
              {"id", "kind", "width_m", "colour_rgb", "polarity", "polyline_m", "dash_m", "gap_m"});
  m.id = y.Integer(node, p, "id");
  const std::string kind = y.Text(node, p, "kind");
  if (const std::optional<MarkingKind> parsed = MarkingKindFromName(kind)) {
    m.kind = *parsed;
  } else if (y.ok()) {
    y.Fail(node["kind"], p + ".kind",
           "one of tape_solid, tape_dashed, stop_bar, crosswalk_stripe, staging_box_edge, joint",
           kind);
  }
  m.width_m = y.Number(node, p, "width_m");
  const YAML::Node colour = y.Child(node, p, "colour_rgb");
  if (colour && y.ExpectSequence(colour, p + ".colour_rgb")) {
    if (colour.size() != 3) {
      y.Fail(colour, p + ".colour_rgb", "3 values [r, g, b]", std::to_string(colour.size()));
    }
    for (std::size_t k = 0; k < 3 && k < colour.size(); ++k) {
      const std::int64_t c = y.IntegerAt(colour[k], internal::IndexPath(p + ".colour_rgb", k));
      m.colour_rgb[k] = c >= 0 && c <= 255 ? static_cast<int>(c) : -1;
    }
  }
  const std::string polarity = y.Text(node, p, "polarity");
  if (polarity == "bright" || polarity == "dark") {
    m.polarity = polarity == "bright" ? MarkingPolarity::kBright : MarkingPolarity::kDark;
  } else if (y.ok()) {
    y.Fail(node["polarity"], p + ".polarity", "'bright' or 'dark'", polarity);
  }
  const YAML::Node polyline = y.Child(node, p, "polyline_m");
  if (polyline && y.ExpectSequence(polyline, p + ".polyline_m")) {
    for (std::size_t j = 0; j < polyline.size() && y.ok(); ++j) {
      const YAML::Node vertex = polyline[j];
      const std::string vp = internal::IndexPath(p + ".polyline_m", j);
      if (!vertex.IsSequence() || vertex.size() != 2) {
        y.Fail(vertex, vp, "a vertex [x, y] in metres", "another value");
        break;
      }
      m.polyline_m.emplace_back(y.NumberAt(vertex[0], vp + "[0]"),
                                y.NumberAt(vertex[1], vp + "[1]"));
    }
  }
  if (y.Child(node, p, "dash_m", false)) m.dash_m = y.Number(node, p, "dash_m");
  if (y.Child(node, p, "gap_m", false)) m.gap_m = y.Number(node, p, "gap_m");
  return m;
}

}  // namespace

std::string_view MarkingKindName(MarkingKind kind) {
  for (const auto& [k, name] : kKindNames) {
    if (k == kind) return name;
  }
  return "unknown";
}

bool IsFaceKind(MarkingKind kind) {
  return kind == MarkingKind::kWall || kind == MarkingKind::kRackFace;
}

std::optional<MarkingKind> MarkingKindFromName(std::string_view name) {
  for (const auto& [k, n] : kKindNames) {
    if (n == name) return k;
  }
  return std::nullopt;
}

namespace internal {

std::optional<FieldProblem> CheckFloorMap(const FloorMap& map) {
  if (map.frame.empty()) return FieldProblem{"frame", "a non-empty frame name", ""};
  if (map.survey) {
    for (const auto& [field, value] :
         {std::pair{"survey.marking_vertex_sigma_m", map.survey->marking_vertex_sigma_m},
          std::pair{"survey.face_offset_sigma_m", map.survey->face_offset_sigma_m},
          std::pair{"survey.face_angle_sigma_rad", map.survey->face_angle_sigma_rad}}) {
      if (!(std::isfinite(value) && value > 0.0)) {
        return FieldProblem{field, "a sigma > 0", FormatShortest(value)};
      }
    }
  }
  std::set<std::int64_t> ids;
  for (std::size_t i = 0; i < map.markings.size(); ++i) {
    const std::string p = IndexPath("markings", i);
    if (auto problem = CheckMarking(map.markings[i], p)) return problem;
    if (!ids.insert(map.markings[i].id).second) {
      return FieldProblem{p + ".id", "an id unique within the map",
                          std::to_string(map.markings[i].id)};
    }
  }
  return std::nullopt;
}

}  // namespace internal

Status FloorMap::Validate() const {
  if (const auto problem = internal::CheckFloorMap(*this)) {
    return internal::ProblemStatus("floor map", *problem);
  }
  return Status::Ok();
}

namespace {

Result<FloorMap> ReadFloorMapUnguarded(const std::filesystem::path& path) {
  return internal::ReadFloorMapInFrame(path, "");
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
Result<FloorMap> ReadFloorMap(const std::filesystem::path& path) {
  return internal::CatchYamlErrors(path.string(), [&] { return ReadFloorMapUnguarded(path); });
}

Result<FloorMap> internal::ReadFloorMapInFrame(const std::filesystem::path& path,
                                               const std::string& expected_frame) {
  Result<YAML::Node> loaded = internal::LoadYamlFile(path);
  if (!loaded.ok()) return loaded.status();
  const YAML::Node& root = *loaded;
  YamlFields y(path.string());
  int major = 0, minor = 0;
  y.CheckFormat(root, kFloorMapFormatName, kFloorMapFormatMajor, kFloorMapFormatMinor, &major,
                &minor);
  if (!y.ok()) return y.status();
  y.CheckKeys(root, "", {"format", "version", "frame", "survey", "markings"});
  FloorMap map;
  map.frame = y.Text(root, "", "frame");
  if (const YAML::Node survey = y.Child(root, "", "survey", false);
      survey && y.ExpectMap(survey, "survey")) {
    y.CheckKeys(survey, "survey",
                {"marking_vertex_sigma_m", "face_offset_sigma_m", "face_angle_sigma_rad"});
    FloorMapSurvey& s = map.survey.emplace();
    s.marking_vertex_sigma_m = y.Number(survey, "survey", "marking_vertex_sigma_m");
    s.face_offset_sigma_m = y.Number(survey, "survey", "face_offset_sigma_m");
    s.face_angle_sigma_rad = y.Number(survey, "survey", "face_angle_sigma_rad");
  }
  if (y.ok() && !expected_frame.empty() && map.frame != expected_frame) {
    y.Fail(root["frame"], "frame", "the dataset's map frame '" + expected_frame + "'", map.frame);
  }
  const YAML::Node markings = y.Child(root, "", "markings");
  if (markings && y.ExpectSequence(markings, "markings")) {
    for (std::size_t i = 0; i < markings.size() && y.ok(); ++i) {
      map.markings.push_back(ParseMarking(y, markings[i], internal::IndexPath("markings", i)));
    }
  }
  if (!y.ok()) return y.status();
  if (const auto problem = internal::CheckFloorMap(map)) {
    y.Fail(internal::LineOfPath(root, problem->field), problem->field, problem->expected,
           problem->got);
    return y.status();
  }
  return map;
}

Status WriteFloorMap(const std::filesystem::path& path, const FloorMap& map) {
  if (Status s = map.Validate(); !s.ok()) return s.WithContext(path.string());
  return WriteFileAtomically(path, internal::FormatFloorMap(map));
}

}  // namespace groundline::core
