// ReadCameraModel: one entry point for the intrinsics formats groundline
// reads, chosen by extension and content:
//
//   *.cameramodel                                   -> mrcal .cameramodel
//   text with a top-level 'distortion_model' key    -> ROS camera_info YAML
//   anything else (.yml, .yaml, .xml, .json, ...)   -> OpenCV calibration file
//
// (camera_info always has 'distortion_model'; OpenCV calibration files never
// do.) The format-specific readers (mrcal_cameramodel_io.h,
// ros_camera_info_io.h, opencv_calibration_io.h) return more: the .cameramodel
// extrinsics, camera_info's R, P and name. Errors are theirs, naming the file
// and the field; this layer adds only "cannot open" errors.
#ifndef GROUNDLINE_CALIBRATION_CAMERA_FILE_H_
#define GROUNDLINE_CALIBRATION_CAMERA_FILE_H_

#include <filesystem>

#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

enum class CameraFileFormat { kMrcalCameraModel, kRosCameraInfo, kOpenCvCalibration };

const char* CameraFileFormatName(CameraFileFormat format);

// The format ReadCameraModel would use; fails only when the file cannot be read.
core::Result<CameraFileFormat> DetectCameraFileFormat(const std::filesystem::path& path);

core::Result<CameraModel> ReadCameraModel(const std::filesystem::path& path);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_CAMERA_FILE_H_
