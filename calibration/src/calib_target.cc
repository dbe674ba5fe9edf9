#include "groundline/calibration/calib_target.h"
#include "groundline/core/yaml_fields.h"

#include <yaml-cpp/yaml.h>

#include <cassert>
#include <cmath>
#include <set>

#include "text_util.h"
#include "yaml_text.h"
#include "yaml_util.h"

namespace groundline::calibration {
namespace {

// Smallest n <= 100 with spacing_ratio * n an integer (to 1e-9): the number
// of grid pitches across one tag.
int PitchesPerTag(double spacing_ratio) {
  for (int n = 1; n <= 100; ++n) {
    const double gap = spacing_ratio * n;
    if (std::abs(gap - std::round(gap)) < 1e-9) return n;
  }
  return -1;
}

class TargetParser {
 public:
  TargetParser(const YAML::Node& node, std::string where) : node_(node), where_(std::move(where)) {}

  template <typename T>
  core::Status Get(const std::string& key, T* out, bool required = true) {
    const YAML::Node value = node_[key];
    if (!value) {
      if (!required) return core::Status::Ok();
      return core::Status::Error(where_ + ": missing field '" + key + "'");
    }
    try {
      *out = value.as<T>();
    } catch (const YAML::Exception&) {
      return core::Status::Error(yaml_util::Where(where_, value) + ": field '" + key +
                                 "': cannot read '" + (value.IsScalar() ? value.Scalar() : "?") +
                                 "' as the expected type");
    }
    return core::Status::Ok();
  }
  core::Status Positive(const std::string& key, double value, double min = 0.0) const {
    if (!(value > min) || !std::isfinite(value)) {
      return core::Status::Error(where_ + ": field '" + key + "': expected > " +
                                 text_util::ShortestDecimal(min) + ", got " +
                                 text_util::ShortestDecimal(value));
    }
    return core::Status::Ok();
  }

 private:
  YAML::Node node_;
  std::string where_;
};

#define GL_RETURN_IF_ERROR(expr)             \
  do {                                       \
    core::Status gl_status_ = (expr);        \
    if (!gl_status_.ok()) return gl_status_; \
  } while (0)

core::Result<CalibTarget> ParseTarget(const YAML::Node& node, const std::string& source) {
  CalibTarget t;
  std::string where = yaml_util::Where(source, node) + ": target";
  TargetParser p(node, where);
  GL_RETURN_IF_ERROR(p.Get("name", &t.name));
  where = source + ": target '" + t.name + "'";
  TargetParser q(node, where);
  std::string type;
  GL_RETURN_IF_ERROR(q.Get("type", &type));
  GL_RETURN_IF_ERROR(q.Get("paper", &t.paper, false));
  if (type == "chessboard") {
    t.type = TargetType::kChessboard;
    GL_RETURN_IF_ERROR(q.Get("inner_corners_x", &t.inner_corners_x));
    GL_RETURN_IF_ERROR(q.Get("inner_corners_y", &t.inner_corners_y));
    GL_RETURN_IF_ERROR(q.Get("square_m", &t.square_m));
    GL_RETURN_IF_ERROR(q.Positive("inner_corners_x", t.inner_corners_x, 1));
    GL_RETURN_IF_ERROR(q.Positive("inner_corners_y", t.inner_corners_y, 1));
    GL_RETURN_IF_ERROR(q.Positive("square_m", t.square_m));
    return t;
  }
  if (type != "aprilgrid" && type != "floor_tag_sheet") {
    return core::Status::Error(where + ": field 'type': expected chessboard, aprilgrid or " +
                               "floor_tag_sheet, got '" + type + "'");
  }
  GL_RETURN_IF_ERROR(q.Get("family", &t.family));
  if (t.family != "tag36h11") {
    return core::Status::Error(where + ": field 'family': only tag36h11 is supported, got '" +
                               t.family + "'");
  }
  GL_RETURN_IF_ERROR(q.Get("tag_size_m", &t.tag_size_m));
  GL_RETURN_IF_ERROR(q.Positive("tag_size_m", t.tag_size_m));
  GL_RETURN_IF_ERROR(q.Get("first_id", &t.first_id, false));
  if (type == "aprilgrid") {
    t.type = TargetType::kAprilGrid;
    GL_RETURN_IF_ERROR(q.Get("tags_x", &t.tags_x));
    GL_RETURN_IF_ERROR(q.Get("tags_y", &t.tags_y));
    GL_RETURN_IF_ERROR(q.Get("spacing_ratio", &t.spacing_ratio));
    GL_RETURN_IF_ERROR(q.Positive("tags_x", t.tags_x));
    GL_RETURN_IF_ERROR(q.Positive("tags_y", t.tags_y));
    GL_RETURN_IF_ERROR(q.Positive("spacing_ratio", t.spacing_ratio));
    if (PitchesPerTag(t.spacing_ratio) < 0) {
      return core::Status::Error(
          where + ": field 'spacing_ratio': " + text_util::ShortestDecimal(t.spacing_ratio) +
          " is not a fraction with a denominator <= 100 (e.g. 0.3, 0.25)");
    }
    t.count = t.tags_x * t.tags_y;
  } else {
    t.type = TargetType::kFloorTagSheet;
    GL_RETURN_IF_ERROR(q.Get("count", &t.count));
    GL_RETURN_IF_ERROR(q.Positive("count", t.count));
    if (t.paper != "A4" && t.paper != "A3") {
      return core::Status::Error(where + ": field 'paper': expected A4 or A3, got '" + t.paper +
                                 "'");
    }
  }
  if (t.first_id < 0 || t.first_id + t.count > 587) {
    return core::Status::Error(where + ": ids " + std::to_string(t.first_id) + ".." +
                               std::to_string(t.first_id + t.count - 1) +
                               " are outside tag36h11's 0..586");
  }
  return t;
}

}  // namespace

const char* TargetTypeName(TargetType type) {
  switch (type) {
    case TargetType::kChessboard:
      return "chessboard";
    case TargetType::kAprilGrid:
      return "aprilgrid";
    case TargetType::kFloorTagSheet:
      return "floor_tag_sheet";
  }
  return "?";
}

Eigen::Vector2d CalibTarget::PatternSize_m() const {
  switch (type) {
    case TargetType::kChessboard:
      return {(inner_corners_x + 1) * square_m, (inner_corners_y + 1) * square_m};
    case TargetType::kAprilGrid: {
      const double gap = spacing_ratio * tag_size_m;
      return {tags_x * tag_size_m + (tags_x - 1) * gap, tags_y * tag_size_m + (tags_y - 1) * gap};
    }
    case TargetType::kFloorTagSheet:
      return {tag_size_m * 1.25, tag_size_m * 1.25};  // with the white quiet zone
  }
  return {0, 0};
}

Eigen::Vector3d BoardGrid::Point_board(int index) const {
  return {(index % width_n) * pitch_m, (index / width_n) * pitch_m, 0.0};
}

BoardGrid MakeBoardGrid(const CalibTarget& target) {
  assert(target.IsBoard());
  BoardGrid grid;
  if (target.type == TargetType::kChessboard) {
    grid.width_n = target.inner_corners_x;
    grid.height_n = target.inner_corners_y;
    grid.pitch_m = target.square_m;
    for (int i = 0; i < grid.width_n * grid.height_n; ++i) grid.observable.push_back(i);
    return grid;
  }
  const int n_tag = PitchesPerTag(target.spacing_ratio);
  assert(n_tag > 0);
  const int n_gap = static_cast<int>(std::lround(target.spacing_ratio * n_tag));
  grid.pitch_m = target.tag_size_m / n_tag;
  grid.width_n = target.tags_x * (n_tag + n_gap) - n_gap + 1;
  grid.height_n = target.tags_y * (n_tag + n_gap) - n_gap + 1;
  for (int id = target.first_id; id < target.first_id + target.count; ++id) {
    for (int k = 0; k < 4; ++k)
      grid.observable.push_back(AprilGridCornerIndex(target, grid, id, k));
  }
  return grid;
}

int AprilGridCornerIndex(const CalibTarget& target, const BoardGrid& grid, int tag_id, int k) {
  assert(target.type == TargetType::kAprilGrid && k >= 0 && k < 4);
  const int i = tag_id - target.first_id;
  if (i < 0 || i >= target.tags_x * target.tags_y) return -1;
  const int n_tag = static_cast<int>(std::lround(target.tag_size_m / grid.pitch_m));
  const int n_gap = static_cast<int>(std::lround(target.spacing_ratio * n_tag));
  const int x0 = (i % target.tags_x) * (n_tag + n_gap);
  const int y0 = (i / target.tags_x) * (n_tag + n_gap);
  // libapriltag's corner order on a printed (y-down) page: bottom-left,
  // bottom-right, top-right, top-left.
  static constexpr int kDx[4] = {0, 1, 1, 0};
  static constexpr int kDy[4] = {1, 1, 0, 0};
  return (y0 + kDy[k] * n_tag) * grid.width_n + x0 + kDx[k] * n_tag;
}

namespace {

core::Result<std::vector<CalibTarget>> ParseCalibTargetsUnguarded(const std::string& yaml_text,
                                                                  const std::string& source_name) {
  core::Result<YAML::Node> root = internal::LoadYamlText(yaml_text, source_name);
  if (!root.ok()) return root.status();
  if (!root->IsMap()) {
    return core::Status::Error(source_name +
                               ": expected a mapping with keys 'format', 'version' and 'targets'");
  }
  if (!(*root)["format"] || (*root)["format"].as<std::string>("") != "groundline-calib-targets") {
    return core::Status::Error(source_name +
                               ": field 'format': expected 'groundline-calib-targets'");
  }
  if ((*root)["version"].as<int>(0) != 1) {
    return core::Status::Error(source_name + ": field 'version': expected 1");
  }
  const YAML::Node list = (*root)["targets"];
  if (!list || !list.IsSequence()) {
    return core::Status::Error(source_name + ": field 'targets': expected a list of targets");
  }
  std::vector<CalibTarget> targets;
  std::set<std::string> names;
  for (const YAML::Node& node : list) {
    core::Result<CalibTarget> target = ParseTarget(node, source_name);
    if (!target.ok()) return target.status();
    if (!names.insert(target->name).second) {
      return core::Status::Error(source_name + ": target '" + target->name + "' defined twice");
    }
    targets.push_back(std::move(target).value());
  }
  return targets;
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
core::Result<std::vector<CalibTarget>> ParseCalibTargets(const std::string& yaml_text,
                                                         const std::string& source_name) {
  return core::internal::CatchYamlErrors(
      source_name, [&] { return ParseCalibTargetsUnguarded(yaml_text, source_name); });
}

core::Result<std::vector<CalibTarget>> ReadCalibTargets(const std::filesystem::path& path) {
  core::Result<std::string> text = text_util::ReadTextFile(path, "targets file");
  if (!text.ok()) return text.status();
  return ParseCalibTargets(*text, path.filename().string());
}

core::Result<CalibTarget> FindCalibTarget(const std::vector<CalibTarget>& targets,
                                          std::string_view name) {
  std::string names;
  for (const CalibTarget& t : targets) {
    if (t.name == name) return t;
    names += (names.empty() ? "" : ", ") + t.name;
  }
  return core::Status::Error("no target named '" + std::string(name) + "'; defined: " + names);
}

}  // namespace groundline::calibration
