#include "opencv_yaml_fields.h"

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>

#include "groundline/core/text_parse.h"
#include "groundline/core/yaml_fields.h"
#include "yaml_text.h"

namespace groundline::calibration::internal {
namespace {

std::optional<double> Number(const YAML::Node& node) {
  return node.IsScalar() ? core::ParseDouble(core::Trim(node.Scalar())) : std::nullopt;
}

std::optional<int> Int(const YAML::Node& node) {
  if (!node.IsScalar()) return std::nullopt;
  const std::optional<std::int64_t> v = core::ParseInt(core::Trim(node.Scalar()));
  if (!v || *v < -(1 << 30) || *v > (1 << 30)) return std::nullopt;
  return static_cast<int>(*v);
}

template <size_t N>
std::string FindKey(const YAML::Node& root, const std::array<const char*, N>& keys) {
  for (const char* key : keys) {
    const YAML::Node node = root[key];
    if (node && !node.IsNull()) return key;
  }
  return "";
}

core::Result<OpenCvNumbers> ReadNumbers(const YAML::Node& node, const std::string& source,
                                        const std::string& key) {
  const std::string where = source + ": key '" + key + "'";
  OpenCvNumbers numbers;
  YAML::Node data = node;
  if (node.IsMap()) {
    const std::optional<int> rows = Int(node["rows"]), cols = Int(node["cols"]);
    if (!rows || !cols || *rows < 1 || *cols < 1 || *rows > kOpenCvMaxMatrixSide ||
        *cols > kOpenCvMaxMatrixSide) {
      return core::Status::Error(where + ": expected an !!opencv-matrix with integer 'rows' and " +
                                 "'cols' in [1, " + std::to_string(kOpenCvMaxMatrixSide) + "]");
    }
    if (!node["dt"] || !node["dt"].IsScalar()) {
      return core::Status::Error(where + ": expected an !!opencv-matrix with 'dt' (e.g. d)");
    }
    data = node["data"];
    if (!data.IsSequence() || data.size() != static_cast<size_t>(*rows * *cols)) {
      return core::Status::Error(
          where + ": expected 'data' to hold rows x cols = " + std::to_string(*rows * *cols) +
          " numbers, got " + (data.IsSequence() ? std::to_string(data.size()) : "none"));
    }
    numbers.rows = *rows;
    numbers.cols = *cols;
  } else if (!node.IsSequence()) {
    return core::Status::Error(where + ": expected an !!opencv-matrix or a list of numbers");
  }
  for (size_t i = 0; i < data.size(); ++i) {
    const std::optional<double> v = Number(data[i]);
    if (!v) {
      return core::Status::Error(where + ": element " + std::to_string(i) + " is not a number");
    }
    numbers.values.push_back(*v);
  }
  if (!node.IsMap()) {
    numbers.rows = 1;
    numbers.cols = static_cast<int>(numbers.values.size());
  }
  return numbers;
}

core::Result<int> ReadSize(const YAML::Node& root, const std::string& source, const char* key) {
  const YAML::Node node = root[key];
  if (!node || node.IsNull()) {
    return core::Status::Error(source + ": missing key '" + key + "' (image size in pixels)");
  }
  const std::optional<int> v = Int(node);
  if (!v || *v <= 0) {
    return core::Status::Error(source + ": key '" + key + "': expected a positive integer (px)");
  }
  return *v;
}

core::Result<OpenCvFields> ReadUnguarded(std::string text, const std::string& source) {
  // OpenCV's "%YAML:1.0" is not a YAML 1.2 directive: blank that line (the
  // line numbers stay right).
  if (text.rfind("%YAML", 0) == 0) text.replace(0, text.find('\n'), "");
  core::Result<YAML::Node> root = LoadYamlText(text, source);
  if (!root.ok()) return root.status();
  if (!root->IsMap()) {
    return core::Status::Error(source +
                               ": expected a mapping with keys 'camera_matrix', "
                               "'distortion_coefficients', 'image_width' and 'image_height'");
  }
  OpenCvFields f;
  f.k_key = FindKey(*root, kOpenCvCameraMatrixKeys);
  if (f.k_key.empty()) {
    return core::Status::Error(source +
                               ": missing key 'camera_matrix' (or 'K', 'cameraMatrix'): "
                               "the 3x3 intrinsic matrix");
  }
  f.d_key = FindKey(*root, kOpenCvDistortionKeys);
  if (f.d_key.empty()) {
    return core::Status::Error(source +
                               ": missing key 'distortion_coefficients' (or 'D', "
                               "'distCoeffs', 'dist_coeffs')");
  }
  core::Result<OpenCvNumbers> k = ReadNumbers((*root)[f.k_key], source, f.k_key);
  if (!k.ok()) return k.status();
  core::Result<OpenCvNumbers> d = ReadNumbers((*root)[f.d_key], source, f.d_key);
  if (!d.ok()) return d.status();
  core::Result<int> width = ReadSize(*root, source, "image_width");
  if (!width.ok()) return width.status();
  core::Result<int> height = ReadSize(*root, source, "image_height");
  if (!height.ok()) return height.status();
  f.k = std::move(k).value();
  f.d = std::move(d).value();
  f.width_px = *width;
  f.height_px = *height;
  return f;
}

}  // namespace

core::Result<OpenCvFields> ReadOpenCvYamlFields(const std::string& text,
                                                const std::string& source) {
  return core::internal::CatchYamlErrors(source, [&] { return ReadUnguarded(text, source); });
}

}  // namespace groundline::calibration::internal
