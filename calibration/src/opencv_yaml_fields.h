// The fields of an OpenCV calibration file (opencv_calibration_io.h) in the
// form ReadOpenCvCalibration checks them, and their reader for OpenCV's YAML
// dialect through yaml-cpp. cv::FileStorage's own YAML parser (OpenCV 4.6)
// loops forever or throws std::length_error on some damaged files (found by
// fuzzing), so YAML never reaches it; XML and JSON still go through it.
#ifndef GROUNDLINE_CALIBRATION_SRC_OPENCV_YAML_FIELDS_H_
#define GROUNDLINE_CALIBRATION_SRC_OPENCV_YAML_FIELDS_H_

#include <array>
#include <string>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::calibration::internal {

inline constexpr std::array<const char*, 3> kOpenCvCameraMatrixKeys = {"camera_matrix", "K",
                                                                       "cameraMatrix"};
inline constexpr std::array<const char*, 4> kOpenCvDistortionKeys = {"distortion_coefficients", "D",
                                                                     "distCoeffs", "dist_coeffs"};
// Larger than any matrix of a calibration file (3x3, 1x14 coefficients).
inline constexpr int kOpenCvMaxMatrixSide = 64;

// A matrix read row-major; a plain list of numbers is 1 x N.
struct OpenCvNumbers {
  std::vector<double> values;
  int rows = 0;
  int cols = 0;
};

struct OpenCvFields {
  std::string k_key;  // the key the camera matrix was found under
  std::string d_key;
  OpenCvNumbers k;
  OpenCvNumbers d;
  int width_px = 0;
  int height_px = 0;
};

// Reads the fields from OpenCV YAML text (a first line "%YAML:1.0" or
// "%YAML 1.0", then a mapping; matrices as !!opencv-matrix maps with rows,
// cols, dt and data, or plain lists). Errors name `source` and the key (a
// syntax error also the line), in the same words as the FileStorage reader.
core::Result<OpenCvFields> ReadOpenCvYamlFields(const std::string& text, const std::string& source);

}  // namespace groundline::calibration::internal

#endif  // GROUNDLINE_CALIBRATION_SRC_OPENCV_YAML_FIELDS_H_
