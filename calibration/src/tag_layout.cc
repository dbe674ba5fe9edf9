#include "groundline/calibration/tag_layout.h"
#include "groundline/core/yaml_fields.h"

#include <yaml-cpp/yaml.h>

#include <cassert>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>

#include "groundline/calibration/tag_detection.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/text_parse.h"
#include "yaml_text.h"
#include "yaml_util.h"

namespace groundline::calibration {
namespace {

using yaml_util::Where;

std::string Describe(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  return "nothing";
}

// The parse context: the file name and the path of the current node for
// messages, e.g. "layout.yaml:7: field 'tags[2].pose.x_m': ...".
struct Ctx {
  const std::string& source;
  std::string path;
  Ctx Sub(const std::string& key) const {
    return {source, path.empty() ? key : path + (key[0] == '[' ? "" : ".") + key};
  }
  core::Status Error(const YAML::Node& node, const std::string& expected) const {
    return core::Status::Error(Where(source, node) + ": field '" + path + "': expected " +
                               expected + ", got " + Describe(node));
  }
};

// Fails on keys outside `allowed` and on missing required keys.
core::Status CheckKeys(const YAML::Node& map, const Ctx& ctx,
                       std::initializer_list<const char*> required,
                       std::initializer_list<const char*> optional = {}) {
  if (!map.IsMap()) return ctx.Error(map, "a mapping");
  for (const auto& entry : map) {
    const std::string key = entry.first.Scalar();
    bool known = false;
    for (const char* k : required) known = known || key == k;
    for (const char* k : optional) known = known || key == k;
    if (!known) {
      return core::Status::Error(Where(ctx.source, entry.first) + ": unknown key '" + key +
                                 "' in '" + (ctx.path.empty() ? "the top level" : ctx.path) +
                                 "' (see docs/tag_layout.md)");
    }
  }
  for (const char* k : required) {
    if (!map[k]) {
      return core::Status::Error(Where(ctx.source, map) + ": missing key '" + k + "' in '" +
                                 (ctx.path.empty() ? "the top level" : ctx.path) + "'");
    }
  }
  return core::Status::Ok();
}

core::Result<double> Number(const YAML::Node& map, const Ctx& parent, const char* key) {
  const YAML::Node node = map[key];
  const Ctx ctx = parent.Sub(key);
  if (node.IsScalar()) {
    if (const std::optional<double> v = core::ParseDouble(node.Scalar()); v && std::isfinite(*v)) {
      return *v;
    }
  }
  return ctx.Error(node, "a finite number");
}

core::Result<core::SE2> Pose(const YAML::Node& map, const Ctx& parent) {
  const YAML::Node node = map["pose"];
  const Ctx ctx = parent.Sub("pose");
  if (core::Status s = CheckKeys(node, ctx, {"x_m", "y_m", "yaw_rad"}); !s.ok()) return s;
  const core::Result<double> x = Number(node, ctx, "x_m");
  if (!x.ok()) return x.status();
  const core::Result<double> y = Number(node, ctx, "y_m");
  if (!y.ok()) return y.status();
  const core::Result<double> yaw = Number(node, ctx, "yaw_rad");
  if (!yaw.ok()) return yaw.status();
  return core::SE2(*x, *y, *yaw);
}

core::Result<SurveyedTag> Tag(const YAML::Node& node, const Ctx& ctx, std::set<int>* ids) {
  if (core::Status s = CheckKeys(node, ctx, {"id", "size_m", "pose"}); !s.ok()) return s;
  SurveyedTag tag;
  const YAML::Node id = node["id"];
  const std::optional<std::int64_t> parsed =
      id.IsScalar() ? core::ParseInt(id.Scalar()) : std::nullopt;
  if (!parsed || *parsed < 0 || *parsed >= Tag36h11Count()) {
    return ctx.Sub("id").Error(id, "a tag36h11 id in 0.." + std::to_string(Tag36h11Count() - 1));
  }
  tag.id = static_cast<int>(*parsed);
  if (!ids->insert(tag.id).second) {
    return ctx.Sub("id").Error(id, "an id not used by another tag");
  }
  const core::Result<double> size = Number(node, ctx, "size_m");
  if (!size.ok()) return size.status();
  if (*size <= 0.0) return ctx.Sub("size_m").Error(node["size_m"], "a tag size > 0 metres");
  tag.size_m = *size;
  core::Result<core::SE2> pose = Pose(node, ctx);
  if (!pose.ok()) return pose.status();
  tag.T_frame_tag = *pose;
  return tag;
}

}  // namespace

std::array<Eigen::Vector2d, 4> SurveyedTag::CornersInFrame() const {
  std::array<Eigen::Vector2d, 4> corners = TagCornersInTagFrame(size_m);
  for (Eigen::Vector2d& c : corners) c = T_frame_tag * c;
  return corners;
}

core::Status TagLayout::Validate() const {
  if (tags.empty()) return core::Status::Error("tag layout: no tags");
  std::set<int> ids;
  for (const SurveyedTag& t : tags) {
    if (t.id < 0 || t.id >= Tag36h11Count() || !ids.insert(t.id).second) {
      return core::Status::Error("tag layout: tag id " + std::to_string(t.id) +
                                 " is out of range or repeated");
    }
    if (!(t.size_m > 0.0) || !t.T_frame_tag.Vector().allFinite()) {
      return core::Status::Error("tag layout: tag " + std::to_string(t.id) +
                                 " needs a size > 0 and a finite pose");
    }
  }
  if (frame == TagLayoutFrame::kBaseLink && !vehicle_poses.empty()) {
    return core::Status::Error("tag layout: frame base_link takes no vehicle_poses");
  }
  if (!(survey_sigma_m >= 0.0) || !std::isfinite(survey_sigma_m)) {
    return core::Status::Error("tag layout: survey_sigma_m must be finite and >= 0");
  }
  std::set<std::string> images;
  for (const VehiclePose& p : vehicle_poses) {
    const bool plain = p.image.find_first_of("\"\\\n\r") == std::string::npos;
    if (p.image.empty() || !plain || !images.insert(p.image).second ||
        !p.T_floor_base.Vector().allFinite()) {
      return core::Status::Error("tag layout: vehicle pose of image '" + p.image +
                                 "' is unnamed, repeated, has quotes, backslashes or line "
                                 "breaks in its name, or is not finite");
    }
  }
  return core::Status::Ok();
}

const SurveyedTag* TagLayout::FindTag(int id) const {
  for (const SurveyedTag& t : tags) {
    if (t.id == id) return &t;
  }
  return nullptr;
}

const VehiclePose* TagLayout::FindPose(const std::string& image) const {
  for (const VehiclePose& p : vehicle_poses) {
    if (p.image == image) return &p;
  }
  return nullptr;
}

namespace {

core::Result<TagLayout> ParseTagLayoutYamlUnguarded(const std::string& yaml_text,
                                                    const std::string& source_name) {
  const core::Result<YAML::Node> loaded = internal::LoadYamlText(yaml_text, source_name);
  if (!loaded.ok()) return loaded.status();
  const YAML::Node& root = *loaded;
  const Ctx top{source_name, ""};
  if (!root.IsMap()) {
    return core::Status::Error(source_name + ": expected a mapping with format: " +
                               kTagLayoutFormat + " at the top level");
  }
  if (core::Status s = CheckKeys(root, top, {"format", "version", "family", "frame", "tags"},
                                 {"vehicle_poses", "survey_sigma_m"});
      !s.ok()) {
    return s;
  }
  const auto expect = [&](const char* key, const std::string& want) -> core::Status {
    const YAML::Node n = root[key];
    if (n.IsScalar() && n.Scalar() == want) return core::Status::Ok();
    return top.Sub(key).Error(n, "'" + want + "'");
  };
  for (const core::Status& s :
       {expect("format", kTagLayoutFormat), expect("version", kTagLayoutVersion),
        expect("family", "tag36h11")}) {
    if (!s.ok()) return s;
  }
  TagLayout layout;
  const YAML::Node frame = root["frame"];
  if (frame.IsScalar() && frame.Scalar() == "floor") {
    layout.frame = TagLayoutFrame::kFloor;
  } else if (frame.IsScalar() && frame.Scalar() == "base_link") {
    layout.frame = TagLayoutFrame::kBaseLink;
  } else {
    return top.Sub("frame").Error(frame, "'floor' or 'base_link'");
  }
  if (root["survey_sigma_m"]) {
    const core::Result<double> sigma = Number(root, top, "survey_sigma_m");
    if (!sigma.ok()) return sigma.status();
    if (*sigma < 0.0) {
      return top.Sub("survey_sigma_m").Error(root["survey_sigma_m"], "a survey error >= 0 metres");
    }
    layout.survey_sigma_m = *sigma;
  }
  const YAML::Node tags = root["tags"];
  if (!tags.IsSequence() || tags.size() == 0) {
    return top.Sub("tags").Error(tags, "a non-empty list of tags");
  }
  std::set<int> ids;
  for (std::size_t i = 0; i < tags.size(); ++i) {
    core::Result<SurveyedTag> tag = Tag(tags[i], top.Sub("tags[" + std::to_string(i) + "]"), &ids);
    if (!tag.ok()) return tag.status();
    layout.tags.push_back(*tag);
  }
  const YAML::Node poses = root["vehicle_poses"];
  if (poses && layout.frame == TagLayoutFrame::kBaseLink) {
    return top.Sub("vehicle_poses")
        .Error(poses,
               "no vehicle_poses with frame: base_link (tags are already in the vehicle "
               "frame; use frame: floor to give one pose per image)");
  }
  if (layout.frame == TagLayoutFrame::kFloor && !poses) {
    return core::Status::Error(source_name +
                               ": frame: floor needs 'vehicle_poses' (the surveyed base_link "
                               "pose of each image in the floor frame)");
  }
  if (poses) {
    if (!poses.IsSequence() || poses.size() == 0) {
      return top.Sub("vehicle_poses").Error(poses, "a non-empty list of {image, pose}");
    }
    std::set<std::string> images;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const Ctx ctx = top.Sub("vehicle_poses[" + std::to_string(i) + "]");
      if (core::Status s = CheckKeys(poses[i], ctx, {"image", "pose"}); !s.ok()) return s;
      const YAML::Node image = poses[i]["image"];
      if (!image.IsScalar() || image.Scalar().empty() || !images.insert(image.Scalar()).second) {
        return ctx.Sub("image").Error(image, "an image file name not used by another pose");
      }
      if (image.Scalar().find_first_of("\"\\\n\r") != std::string::npos) {
        return ctx.Sub("image").Error(
            image, "an image file name without quotes, backslashes or line breaks");
      }
      core::Result<core::SE2> pose = Pose(poses[i], ctx);
      if (!pose.ok()) return pose.status();
      layout.vehicle_poses.push_back({image.Scalar(), *pose});
    }
  }
  return layout;
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
core::Result<TagLayout> ParseTagLayoutYaml(const std::string& yaml_text,
                                           const std::string& source_name) {
  return core::internal::CatchYamlErrors(
      source_name, [&] { return ParseTagLayoutYamlUnguarded(yaml_text, source_name); });
}

core::Result<TagLayout> ReadTagLayout(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return core::Status::Error(path.string() + ": cannot open the tag layout file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return core::Status::Error(path.string() + ": read error");
  return ParseTagLayoutYaml(text.str(), path.string());
}

std::string TagLayoutToYaml(const TagLayout& layout) {
  assert(layout.Validate().ok());
  const auto num = [](double v) { return core::FormatYamlDouble(v); };
  const auto pose = [&](const core::SE2& T) {
    return "{x_m: " + num(T.x()) + ", y_m: " + num(T.y()) + ", yaw_rad: " + num(T.yaw()) + "}";
  };
  std::ostringstream out;
  out << "# groundline tag layout: tag36h11 tags lying on the floor; see docs/tag_layout.md.\n"
      << "# size_m: edge of the outer black square; pose: tag centre, x to the printed\n"
      << "# tag's right, y to its top. Metres and radians.\n"
      << "format: " << kTagLayoutFormat << "\nversion: \"" << kTagLayoutVersion << "\"\n"
      << "family: tag36h11\nframe: "
      << (layout.frame == TagLayoutFrame::kFloor ? "floor" : "base_link") << "\n";
  if (layout.survey_sigma_m > 0.0) {
    out << "survey_sigma_m: " << num(layout.survey_sigma_m)
        << "  # 1-sigma error of each surveyed tag corner, per axis\n";
  }
  out << "tags:\n";
  for (const SurveyedTag& t : layout.tags) {
    out << "  - {id: " << t.id << ", size_m: " << num(t.size_m) << ", pose: " << pose(t.T_frame_tag)
        << "}\n";
  }
  if (!layout.vehicle_poses.empty()) {
    out << "vehicle_poses:  # base_link in the floor frame when the image was taken\n";
    for (const VehiclePose& p : layout.vehicle_poses) {
      out << "  - {image: \"" << p.image << "\", pose: " << pose(p.T_floor_base) << "}\n";
    }
  }
  return out.str();
}

core::Status WriteTagLayout(const TagLayout& layout, const std::filesystem::path& path) {
  if (core::Status s = layout.Validate(); !s.ok()) return s.WithContext(path.string());
  return core::WriteFileAtomically(path, TagLayoutToYaml(layout));
}

}  // namespace groundline::calibration
