#include "report_config.h"

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>

#include "groundline/core/text_parse.h"
#include "groundline/core/yaml_fields.h"
#include "text_util.h"
#include "yaml_text.h"
#include "yaml_util.h"

namespace groundline::calibration::internal {
namespace {

// Parses the scalar into the target; false when it is not of the target's type.
bool Assign(const YAML::Node& value, const std::variant<double*, int*, bool*>& target) {
  if (!value.IsScalar()) return false;
  const std::string& text = value.Scalar();
  if (double* const* d = std::get_if<double*>(&target)) {
    const std::optional<double> v = core::ParseDouble(text);
    if (!v || !std::isfinite(*v)) return false;
    **d = *v;
  } else if (int* const* i = std::get_if<int*>(&target)) {
    const std::optional<std::int64_t> v = core::ParseInt(text);
    if (!v || *v < -1000000 || *v > 1000000) return false;
    **i = static_cast<int>(*v);
  } else {
    if (text != "true" && text != "false") return false;
    *std::get<bool*>(target) = text == "true";
  }
  return true;
}

const char* Expected(const std::variant<double*, int*, bool*>& target) {
  if (std::holds_alternative<double*>(target)) return "a number";
  if (std::holds_alternative<int*>(target)) return "an integer";
  return "true or false";
}

}  // namespace

namespace {

core::Status ReadConfigSectionUnguarded(const std::filesystem::path& path, const char* section,
                                        std::initializer_list<ConfigField> fields) {
  core::Result<std::string> text = text_util::ReadTextFile(path, "report config");
  if (!text.ok()) return text.status();
  const std::string source = path.string();
  core::Result<YAML::Node> root = LoadYamlText(*text, source);
  if (!root.ok()) return root.status();
  if (!root->IsMap() || !(*root)[section]) return core::Status::Ok();
  const YAML::Node node = (*root)[section];
  if (!node.IsMap()) {
    return core::Status::Error(yaml_util::Where(source, node) + ": key '" + section +
                               "': expected a mapping of thresholds");
  }
  for (const auto& entry : node) {
    const std::string key = entry.first.Scalar();
    const std::string where =
        yaml_util::Where(source, entry.first) + ": key '" + section + "." + key + "'";
    const ConfigField* field = nullptr;
    for (const ConfigField& f : fields) {
      if (key == f.key) field = &f;
    }
    if (field == nullptr) {
      std::string known;
      for (const ConfigField& f : fields) known += (known.empty() ? "" : ", ") + std::string(f.key);
      return core::Status::Error(where + ": unknown key (expected one of " + known +
                                 "; docs/calibration.md)");
    }
    if (!Assign(entry.second, field->target)) {
      return core::Status::Error(
          where + ": expected " + Expected(field->target) + ", got '" +
          (entry.second.IsScalar() ? entry.second.Scalar() : "a collection") + "'");
    }
  }
  return core::Status::Ok();
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
core::Status ReadConfigSection(const std::filesystem::path& path, const char* section,
                               std::initializer_list<ConfigField> fields) {
  return core::internal::CatchYamlErrors(
      path.string(), [&] { return ReadConfigSectionUnguarded(path, section, fields); });
}

}  // namespace groundline::calibration::internal
