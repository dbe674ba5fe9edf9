// ROS camera_info YAML, as camera_calibration_parsers reads and writes it:
//
//   image_width: 640                     (px)
//   image_height: 480
//   camera_name: front
//   camera_matrix: {rows: 3, cols: 3, data: [fx, 0, cx, 0, fy, cy, 0, 0, 1]}
//   distortion_model: plumb_bob          (or rational_polynomial)
//   distortion_coefficients: {rows: 1, cols: 5, data: [k1, k2, p1, p2, k3]}
//   rectification_matrix: {rows: 3, cols: 3, data: [...]}   (R, row-major)
//   projection_matrix: {rows: 3, cols: 4, data: [...]}       (P, row-major)
//
// The raw camera is K with the distortion; R and P describe the rectified
// image (R the rotation into the rectified frame, P its 3x4 pinhole
// projection). Models:
//   plumb_bob           5 coefficients k1 k2 p1 p2 k3  -> LENSMODEL_OPENCV5
//                       (4 coefficients are accepted  -> LENSMODEL_OPENCV4)
//   rational_polynomial 8 coefficients k1 k2 p1 p2 k3 k4 k5 k6 -> LENSMODEL_OPENCV8
// 'equidistant' (the Kannala-Brandt fisheye) has no mrcal 2.2 equivalent and
// is rejected, as are other names and counts. Writing: OPENCV4 (as plumb_bob
// with k3 = 0), OPENCV5, OPENCV8 and PINHOLE (plumb_bob with zeros); other
// models are refused. Numbers are written in their shortest exact form, with
// a '.' in every exponent form ("9.0e-04") so that PyYAML reads them as floats.
//
// Every key above is required (camera_name may be empty); errors name the
// file, the line and the key, e.g.
//   "info.yaml:4: key 'camera_matrix': expected 9 numbers in 'data', got 8".
#ifndef GROUNDLINE_CALIBRATION_ROS_CAMERA_INFO_IO_H_
#define GROUNDLINE_CALIBRATION_ROS_CAMERA_INFO_IO_H_

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct RosCameraInfo {
  CameraModel camera;
  std::string camera_name;
  Eigen::Matrix3d rectification = Eigen::Matrix3d::Identity();  // R
  Eigen::Matrix<double, 3, 4> projection;                       // P, px
};

// camera_info for a monocular camera: R = I and P = [K | 0].
RosCameraInfo MakeRosCameraInfo(const CameraModel& camera, const std::string& camera_name);

core::Result<RosCameraInfo> ParseRosCameraInfo(const std::string& yaml_text,
                                               const std::string& source_name);
core::Result<RosCameraInfo> ReadRosCameraInfo(const std::filesystem::path& path);

// Fails for lens models camera_info cannot express.
core::Result<std::string> RosCameraInfoToYaml(const RosCameraInfo& info);
// Writes atomically (PATH.tmp.<pid>, then renamed over PATH).
core::Status WriteRosCameraInfo(const std::filesystem::path& path, const RosCameraInfo& info);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_ROS_CAMERA_INFO_IO_H_
