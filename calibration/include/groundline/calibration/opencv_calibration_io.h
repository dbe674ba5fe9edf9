// OpenCV calibration files (YAML "%YAML:1.0", XML or JSON), as OpenCV's
// calibration sample and cv::calibrateCamera users write them. YAML is read
// with yaml-cpp (OpenCV 4.6's own YAML parser can hang on damaged files),
// XML and JSON with cv::FileStorage:
//
//   image_width: 640                        (px, integer > 0)
//   image_height: 480
//   camera_matrix: !!opencv-matrix          (3x3, [fx 0 cx; 0 fy cy; 0 0 1], px;
//      rows: 3  cols: 3  dt: d  data: [...]  also read from key 'K' or 'cameraMatrix')
//   distortion_coefficients: !!opencv-matrix (1xN or Nx1; also 'D', 'distCoeffs',
//      rows: 5  cols: 1  dt: d  data: [...]  'dist_coeffs')
//
// Either matrix may also be a plain sequence of numbers (row-major). The
// distortion vector is OpenCV's (k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4]]]),
// the same equations and order as mrcal's OPENCV models:
//   4 -> LENSMODEL_OPENCV4, 5 -> OPENCV5, 8 -> OPENCV8, 12 -> OPENCV12.
// 14 coefficients (the tilted-sensor model, tauX tauY) and other counts are
// rejected, as is a camera matrix with skew (mrcal has none). Other keys
// (nframes, avg_reprojection_error, ...) are ignored.
//
// Writing uses cv::FileStorage's YAML, whose "%.16e" doubles read back
// exactly. PINHOLE is written with five zero coefficients (it reads back as
// OPENCV5 with zero distortion: the same projection). Other lens models have
// no OpenCV equivalent and are refused.
//
// Errors name the file and the key, e.g.
//   "left.yml: key 'distortion_coefficients': expected 4, 5, 8 or 12 values, got 14 (...)".
#ifndef GROUNDLINE_CALIBRATION_OPENCV_CALIBRATION_IO_H_
#define GROUNDLINE_CALIBRATION_OPENCV_CALIBRATION_IO_H_

#include <filesystem>
#include <string>

#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

core::Result<CameraModel> ReadOpenCvCalibration(const std::filesystem::path& path);

// The YAML text of a camera; fails for models without an OpenCV equivalent.
core::Result<std::string> OpenCvCalibrationToYaml(const CameraModel& camera);

// Writes the YAML atomically (PATH.tmp.<pid>, then renamed over PATH).
core::Status WriteOpenCvCalibration(const std::filesystem::path& path, const CameraModel& camera);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_OPENCV_CALIBRATION_IO_H_
