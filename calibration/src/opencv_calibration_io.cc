#include "groundline/calibration/opencv_calibration_io.h"

#include <opencv2/core.hpp>

#include <array>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "groundline/core/atomic_file.h"
#include "opencv_yaml_fields.h"
#include "text_util.h"

namespace groundline::calibration {
namespace {

using internal::OpenCvFields;
using internal::OpenCvNumbers;

// The first present key of `keys`, or "" when none is.
template <size_t N>
std::string FindKey(const cv::FileStorage& fs, const std::array<const char*, N>& keys) {
  for (const char* key : keys) {
    if (!fs[key].empty() && !fs[key].isNone()) return key;
  }
  return "";
}

// Reads an !!opencv-matrix or a plain sequence of numbers.
core::Result<OpenCvNumbers> ReadNumbers(const cv::FileNode& node, const std::string& where) {
  OpenCvNumbers numbers;
  if (node.isSeq()) {
    for (size_t i = 0; i < node.size(); ++i) {
      const cv::FileNode item = node[static_cast<int>(i)];
      if (!item.isReal() && !item.isInt()) {
        return core::Status::Error(where + ": element " + std::to_string(i) + " is not a number");
      }
      numbers.values.push_back(static_cast<double>(item));
    }
    numbers.rows = 1;
    numbers.cols = static_cast<int>(numbers.values.size());
    return numbers;
  }
  if (!node.isMap()) {
    return core::Status::Error(where + ": expected an !!opencv-matrix or a list of numbers");
  }
  // OpenCV allocates rows x cols before it reads 'data': check the sizes
  // first, so that a damaged header cannot ask for gigabytes (found by fuzzing).
  constexpr int kMax = internal::kOpenCvMaxMatrixSide;
  const cv::FileNode rows = node["rows"], cols = node["cols"], data = node["data"];
  if (!rows.isInt() || !cols.isInt() || static_cast<int>(rows) < 1 || static_cast<int>(cols) < 1 ||
      static_cast<int>(rows) > kMax || static_cast<int>(cols) > kMax) {
    return core::Status::Error(where +
                               ": expected an !!opencv-matrix with integer 'rows' and "
                               "'cols' in [1, " +
                               std::to_string(kMax) + "]");
  }
  if (!data.isSeq() ||
      data.size() != static_cast<size_t>(static_cast<int>(rows) * static_cast<int>(cols))) {
    return core::Status::Error(where + ": expected 'data' to hold rows x cols = " +
                               std::to_string(static_cast<int>(rows) * static_cast<int>(cols)) +
                               " numbers, got " +
                               (data.isSeq() ? std::to_string(data.size()) : std::string("none")));
  }
  cv::Mat matrix;
  try {
    node >> matrix;
  } catch (const cv::Exception& e) {
    return core::Status::Error(where + ": not a readable !!opencv-matrix (" + e.err + ")");
  }
  if (matrix.empty() || matrix.channels() != 1) {
    return core::Status::Error(where +
                               ": expected a one-channel !!opencv-matrix with rows, cols, "
                               "dt and data");
  }
  cv::Mat as_double;
  matrix.convertTo(as_double, CV_64F);
  numbers.rows = as_double.rows;
  numbers.cols = as_double.cols;
  for (int r = 0; r < as_double.rows; ++r) {
    for (int c = 0; c < as_double.cols; ++c) numbers.values.push_back(as_double.at<double>(r, c));
  }
  return numbers;
}

core::Result<int> ReadSize(const cv::FileStorage& fs, const std::string& source, const char* key) {
  const cv::FileNode node = fs[key];
  if (node.empty() || node.isNone()) {
    return core::Status::Error(source + ": missing key '" + key + "' (image size in pixels)");
  }
  if (!node.isInt() || static_cast<int>(node) <= 0) {
    return core::Status::Error(source + ": key '" + key + "': expected a positive integer (px)");
  }
  return static_cast<int>(node);
}

// The fields of an XML or JSON file, through cv::FileStorage.
core::Result<OpenCvFields> ReadStorageFields(const std::string& text, const std::string& source) {
  cv::FileStorage fs;
  try {
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& e) {
    return core::Status::Error(source + ": OpenCV's FileStorage cannot parse it: " + e.err);
  } catch (const std::exception& e) {
    return core::Status::Error(source + ": OpenCV's FileStorage cannot parse it: " + e.what());
  }
  if (!fs.isOpened()) {
    return core::Status::Error(source + ": OpenCV's FileStorage cannot parse it");
  }
  // fs[key] asserts (throws cv::Exception) on a document that is not a mapping.
  if (!fs.root().isMap()) {
    return core::Status::Error(source +
                               ": expected a mapping with keys 'camera_matrix', "
                               "'distortion_coefficients', 'image_width' and 'image_height'");
  }
  OpenCvFields f;
  try {
    f.k_key = FindKey(fs, internal::kOpenCvCameraMatrixKeys);
    if (f.k_key.empty()) {
      return core::Status::Error(source +
                                 ": missing key 'camera_matrix' (or 'K', 'cameraMatrix'): "
                                 "the 3x3 intrinsic matrix");
    }
    f.d_key = FindKey(fs, internal::kOpenCvDistortionKeys);
    if (f.d_key.empty()) {
      return core::Status::Error(source +
                                 ": missing key 'distortion_coefficients' (or 'D', "
                                 "'distCoeffs', 'dist_coeffs')");
    }
    core::Result<OpenCvNumbers> k = ReadNumbers(fs[f.k_key], source + ": key '" + f.k_key + "'");
    if (!k.ok()) return k.status();
    core::Result<OpenCvNumbers> d = ReadNumbers(fs[f.d_key], source + ": key '" + f.d_key + "'");
    if (!d.ok()) return d.status();
    core::Result<int> width = ReadSize(fs, source, "image_width");
    if (!width.ok()) return width.status();
    core::Result<int> height = ReadSize(fs, source, "image_height");
    if (!height.ok()) return height.status();
    f.k = std::move(k).value();
    f.d = std::move(d).value();
    f.width_px = *width;
    f.height_px = *height;
  } catch (const cv::Exception& e) {
    return core::Status::Error(source +
                               ": unexpected structure for OpenCV's FileStorage: " + e.err);
  }
  return f;
}

const char* ModelForCount(size_t count) {
  switch (count) {
    case 4:
      return "LENSMODEL_OPENCV4";
    case 5:
      return "LENSMODEL_OPENCV5";
    case 8:
      return "LENSMODEL_OPENCV8";
    case 12:
      return "LENSMODEL_OPENCV12";
    default:
      return nullptr;
  }
}

// The camera of the fields: K a 3x3 [fx 0 cx; 0 fy cy; 0 0 1], D a vector of
// 4, 5, 8 or 12 coefficients.
core::Result<CameraModel> CameraFromFields(const OpenCvFields& f, const std::string& source) {
  const std::string k_where = source + ": key '" + f.k_key + "'";
  const std::string d_where = source + ": key '" + f.d_key + "'";
  const OpenCvNumbers& k = f.k;
  if (k.values.size() != 9 || (k.rows != 3 && k.rows != 1)) {
    return core::Status::Error(k_where + ": expected a 3x3 matrix, got " + std::to_string(k.rows) +
                               "x" + std::to_string(k.cols));
  }
  const std::vector<double>& m = k.values;
  if (m[3] != 0.0 || m[6] != 0.0 || m[7] != 0.0 || m[8] != 1.0) {
    return core::Status::Error(k_where + ": expected [fx 0 cx; 0 fy cy; 0 0 1]");
  }
  if (m[1] != 0.0) {
    return core::Status::Error(k_where + ": skew K(0,1) = " + text_util::ShortestDecimal(m[1]) +
                               " is not supported (mrcal models have no skew)");
  }
  const OpenCvNumbers& d = f.d;
  if (d.rows != 1 && d.cols != 1) {
    return core::Status::Error(d_where + ": expected a 1xN or Nx1 vector, got " +
                               std::to_string(d.rows) + "x" + std::to_string(d.cols));
  }
  const char* model = ModelForCount(d.values.size());
  if (model == nullptr) {
    std::string why = d.values.size() == 14
                          ? " (the 14-coefficient tilted-sensor model has no mrcal equivalent)"
                          : "";
    return core::Status::Error(d_where +
                               ": expected 4, 5, 8 or 12 values (OpenCV k1 k2 p1 p2 "
                               "[k3 [k4 k5 k6 [s1 s2 s3 s4]]]), got " +
                               std::to_string(d.values.size()) + why);
  }
  std::vector<double> intrinsics = {m[0], m[4], m[2], m[5]};
  intrinsics.insert(intrinsics.end(), d.values.begin(), d.values.end());
  core::Result<CameraModel> camera =
      CameraModel::Create(model, std::move(intrinsics), f.width_px, f.height_px);
  if (!camera.ok()) return camera.status().WithContext(k_where + " / '" + f.d_key + "'");
  return camera;
}

}  // namespace

core::Result<CameraModel> ReadOpenCvCalibration(const std::filesystem::path& path) {
  const std::string source = path.string();
  core::Result<std::string> text = text_util::ReadTextFile(path, "OpenCV calibration file");
  if (!text.ok()) return text.status();
  // YAML through yaml-cpp (opencv_yaml_fields.h says why); XML and JSON
  // through cv::FileStorage.
  const size_t first = text->find_first_not_of(" \t\r\n");
  const bool yaml = first == std::string::npos || ((*text)[first] != '<' && (*text)[first] != '{');
  const core::Result<OpenCvFields> fields =
      yaml ? internal::ReadOpenCvYamlFields(*text, source) : ReadStorageFields(*text, source);
  if (!fields.ok()) return fields.status();
  return CameraFromFields(*fields, source);
}

core::Result<std::string> OpenCvCalibrationToYaml(const CameraModel& camera) {
  const std::vector<double>& p = camera.intrinsics();
  std::vector<double> distortion;
  switch (camera.family()) {
    case LensFamily::kPinhole:
      distortion.assign(5, 0.0);
      break;
    case LensFamily::kOpenCv4:
    case LensFamily::kOpenCv5:
    case LensFamily::kOpenCv8:
    case LensFamily::kOpenCv12:
      distortion.assign(p.begin() + 4, p.end());
      break;
    default:
      return core::Status::Error("lens model " + camera.lens_model() +
                                 " has no OpenCV equivalent; write a .cameramodel instead");
  }
  const cv::Matx33d K(p[0], 0.0, p[2], 0.0, p[1], p[3], 0.0, 0.0, 1.0);
  cv::FileStorage fs(
      ".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  fs << "image_width" << camera.width_px();
  fs << "image_height" << camera.height_px();
  fs << "camera_matrix" << cv::Mat(K);
  fs << "distortion_coefficients" << cv::Mat(distortion, true);
  return fs.releaseAndGetString();
}

core::Status WriteOpenCvCalibration(const std::filesystem::path& path, const CameraModel& camera) {
  core::Result<std::string> text = OpenCvCalibrationToYaml(camera);
  if (!text.ok()) return text.status().WithContext(path.string());
  return core::WriteFileAtomically(path, *text);
}

}  // namespace groundline::calibration
