#include "groundline/calibration/ros_camera_info_io.h"
#include "groundline/core/yaml_fields.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "groundline/core/atomic_file.h"
#include "text_util.h"
#include "yaml_text.h"
#include "yaml_util.h"

namespace groundline::calibration {
namespace {

using yaml_util::KeyWhere;
using yaml_util::Where;

core::Result<YAML::Node> Require(const YAML::Node& root, const std::string& source, const char* key,
                                 const char* meaning) {
  const YAML::Node node = root[key];
  if (!node) return core::Status::Error(source + ": missing key '" + key + "' (" + meaning + ")");
  return node;
}

core::Result<int> ReadInt(const YAML::Node& node, const std::string& where) {
  try {
    if (node.IsScalar()) return node.as<int>();
  } catch (const YAML::Exception&) {
  }
  return core::Status::Error(where + ": expected an integer");
}

// A {rows, cols, data} matrix; rows x cols must be one of the given shapes.
core::Result<std::vector<double>> ReadMatrix(const YAML::Node& root, const std::string& source,
                                             const char* key, const char* meaning,
                                             const std::vector<std::pair<int, int>>& shapes) {
  core::Result<YAML::Node> found = Require(root, source, key, meaning);
  if (!found.ok()) return found.status();
  const YAML::Node& node = *found;  // const: absent keys must not be inserted
  const std::string where = KeyWhere(root, source, key);
  if (!node.IsMap() || !node["rows"] || !node["cols"] || !node["data"]) {
    return core::Status::Error(where + ": expected a mapping with rows, cols and data");
  }
  core::Result<int> rows = ReadInt(node["rows"], where + " rows");
  if (!rows.ok()) return rows.status();
  core::Result<int> cols = ReadInt(node["cols"], where + " cols");
  if (!cols.ok()) return cols.status();
  bool shape_ok = false;
  std::string expected;
  for (const auto& [r, c] : shapes) {
    shape_ok = shape_ok || (*rows == r && *cols == c);
    expected += (expected.empty() ? "" : " or ") + std::to_string(r) + "x" + std::to_string(c);
  }
  if (!shape_ok) {
    return core::Status::Error(where + ": expected a " + expected + " matrix, got " +
                               std::to_string(*rows) + "x" + std::to_string(*cols));
  }
  const YAML::Node data = node["data"];
  const size_t count = static_cast<size_t>(*rows) * static_cast<size_t>(*cols);
  if (!data.IsSequence() || data.size() != count) {
    return core::Status::Error(where + ": expected " + std::to_string(count) +
                               " numbers in 'data', got " +
                               (data.IsSequence() ? std::to_string(data.size()) : "no list"));
  }
  std::vector<double> values;
  for (size_t i = 0; i < count; ++i) {
    double value = 0.0;
    bool ok = data[i].IsScalar();
    try {
      if (ok) value = data[i].as<double>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
    if (!ok || !std::isfinite(value)) {
      return core::Status::Error(Where(source, data[i]) + ": key '" + key + "' data[" +
                                 std::to_string(i) + "]: expected a finite number, got '" +
                                 (data[i].IsScalar() ? data[i].Scalar() : "a non-scalar") + "'");
    }
    values.push_back(value);
  }
  return values;
}

std::string MatrixYaml(const char* key, int rows, int cols, const double* row_major) {
  std::string out = std::string(key) + ":\n  rows: " + std::to_string(rows) +
                    "\n  cols: " + std::to_string(cols) + "\n  data: [";
  for (int i = 0; i < rows * cols; ++i) {
    out += (i == 0 ? "" : ", ") + text_util::YamlDecimal(row_major[i]);
  }
  return out + "]\n";
}

std::string DoubleQuoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

RosCameraInfo MakeRosCameraInfo(const CameraModel& camera, const std::string& camera_name) {
  RosCameraInfo info{camera, camera_name, Eigen::Matrix3d::Identity(),
                     Eigen::Matrix<double, 3, 4>::Zero()};
  info.projection.leftCols<3>() = camera.K();
  return info;
}

namespace {

core::Result<RosCameraInfo> ParseRosCameraInfoUnguarded(const std::string& yaml_text,
                                                        const std::string& source_name) {
  const core::Result<YAML::Node> loaded = internal::LoadYamlText(yaml_text, source_name);
  if (!loaded.ok()) return loaded.status();
  const YAML::Node& root = *loaded;  // const: absent keys must not be inserted
  if (!root.IsMap()) return core::Status::Error(source_name + ": expected a camera_info mapping");

  core::Result<YAML::Node> width_node = Require(root, source_name, "image_width", "px");
  if (!width_node.ok()) return width_node.status();
  core::Result<int> width = ReadInt(*width_node, KeyWhere(root, source_name, "image_width"));
  if (!width.ok()) return width.status();
  core::Result<YAML::Node> height_node = Require(root, source_name, "image_height", "px");
  if (!height_node.ok()) return height_node.status();
  core::Result<int> height = ReadInt(*height_node, KeyWhere(root, source_name, "image_height"));
  if (!height.ok()) return height.status();

  if (*width <= 0 || *height <= 0) {
    return core::Status::Error(KeyWhere(root, source_name, "image_width") +
                               " / 'image_height': expected positive sizes (px), "
                               "got " +
                               std::to_string(*width) + " x " + std::to_string(*height));
  }
  core::Result<std::vector<double>> k =
      ReadMatrix(root, source_name, "camera_matrix", "3x3 intrinsic matrix K", {{3, 3}});
  if (!k.ok()) return k.status();
  const std::vector<double>& K = *k;
  const std::string k_where = KeyWhere(root, source_name, "camera_matrix");
  if (K[1] != 0.0 || K[3] != 0.0 || K[6] != 0.0 || K[7] != 0.0 || K[8] != 1.0) {
    return core::Status::Error(k_where + ": expected [fx 0 cx; 0 fy cy; 0 0 1] (no skew)");
  }
  core::Result<YAML::Node> model_node =
      Require(root, source_name, "distortion_model", "plumb_bob or rational_polynomial");
  if (!model_node.ok()) return model_node.status();
  const std::string model_name = model_node->IsScalar() ? model_node->Scalar() : "";
  const std::string model_where = KeyWhere(root, source_name, "distortion_model");
  std::vector<std::pair<int, int>> shapes;
  if (model_name == "plumb_bob") {
    shapes = {{1, 5}, {5, 1}, {1, 4}, {4, 1}};
  } else if (model_name == "rational_polynomial") {
    shapes = {{1, 8}, {8, 1}};
  } else if (model_name == "equidistant") {
    return core::Status::Error(model_where +
                               ": 'equidistant' (Kannala-Brandt fisheye) has no mrcal "
                               "2.2 lens model; recalibrate with LENSMODEL_OPENCV8 or "
                               "a splined model");
  } else {
    return core::Status::Error(model_where + ": expected plumb_bob or rational_polynomial, got '" +
                               model_name + "'");
  }
  core::Result<std::vector<double>> d =
      ReadMatrix(root, source_name, "distortion_coefficients", "the distortion vector", shapes);
  if (!d.ok()) return d.status();
  core::Result<std::vector<double>> r =
      ReadMatrix(root, source_name, "rectification_matrix", "3x3 rectifying rotation R", {{3, 3}});
  if (!r.ok()) return r.status();
  core::Result<std::vector<double>> p =
      ReadMatrix(root, source_name, "projection_matrix", "3x4 projection P", {{3, 4}});
  if (!p.ok()) return p.status();
  const YAML::Node name_node = root["camera_name"];
  if (!name_node) {
    return core::Status::Error(source_name + ": missing key 'camera_name' (may be empty)");
  }

  const char* lens = d->size() == 8   ? "LENSMODEL_OPENCV8"
                     : d->size() == 5 ? "LENSMODEL_OPENCV5"
                                      : "LENSMODEL_OPENCV4";
  std::vector<double> intrinsics = {K[0], K[4], K[2], K[5]};
  intrinsics.insert(intrinsics.end(), d->begin(), d->end());
  core::Result<CameraModel> camera =
      CameraModel::Create(lens, std::move(intrinsics), *width, *height);
  if (!camera.ok()) return camera.status().WithContext(k_where);
  RosCameraInfo info{std::move(camera).value(), name_node.IsScalar() ? name_node.Scalar() : "",
                     Eigen::Matrix3d::Identity(), Eigen::Matrix<double, 3, 4>::Zero()};
  for (int i = 0; i < 9; ++i) info.rectification(i / 3, i % 3) = (*r)[static_cast<size_t>(i)];
  for (int i = 0; i < 12; ++i) info.projection(i / 4, i % 4) = (*p)[static_cast<size_t>(i)];
  return info;
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
core::Result<RosCameraInfo> ParseRosCameraInfo(const std::string& yaml_text,
                                               const std::string& source_name) {
  return core::internal::CatchYamlErrors(
      source_name, [&] { return ParseRosCameraInfoUnguarded(yaml_text, source_name); });
}

core::Result<RosCameraInfo> ReadRosCameraInfo(const std::filesystem::path& path) {
  core::Result<std::string> text = text_util::ReadTextFile(path, "camera_info file");
  if (!text.ok()) return text.status();
  return ParseRosCameraInfo(*text, path.string());
}

core::Result<std::string> RosCameraInfoToYaml(const RosCameraInfo& info) {
  const CameraModel& camera = info.camera;
  const std::vector<double>& p = camera.intrinsics();
  std::vector<double> distortion(p.begin() + 4, p.end());
  std::string model = "plumb_bob";
  switch (camera.family()) {
    case LensFamily::kPinhole:
      distortion.assign(5, 0.0);
      break;
    case LensFamily::kOpenCv4:
      distortion.push_back(0.0);
      break;  // k3 = 0: the same model
    case LensFamily::kOpenCv5:
      break;
    case LensFamily::kOpenCv8:
      model = "rational_polynomial";
      break;
    default:
      return core::Status::Error("lens model " + camera.lens_model() +
                                 " has no ROS camera_info distortion_model; write a .cameramodel");
  }
  if (!info.rectification.allFinite() || !info.projection.allFinite()) {
    return core::Status::Error("camera_info R or P has non-finite entries");
  }
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> K = camera.K();
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R = info.rectification;
  const Eigen::Matrix<double, 3, 4, Eigen::RowMajor> P = info.projection;
  std::ostringstream out;
  out << "image_width: " << camera.width_px() << "\n"
      << "image_height: " << camera.height_px() << "\n"
      << "camera_name: " << DoubleQuoted(info.camera_name) << "\n"
      << MatrixYaml("camera_matrix", 3, 3, K.data()) << "distortion_model: " << model << "\n"
      << MatrixYaml("distortion_coefficients", 1, static_cast<int>(distortion.size()),
                    distortion.data())
      << MatrixYaml("rectification_matrix", 3, 3, R.data())
      << MatrixYaml("projection_matrix", 3, 4, P.data());
  return out.str();
}

core::Status WriteRosCameraInfo(const std::filesystem::path& path, const RosCameraInfo& info) {
  core::Result<std::string> text = RosCameraInfoToYaml(info);
  if (!text.ok()) return text.status().WithContext(path.string());
  return core::WriteFileAtomically(path, *text);
}

}  // namespace groundline::calibration
