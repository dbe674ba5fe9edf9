#include "groundline/calibration/camera_file.h"

#include <regex>
#include <string>

#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "text_util.h"

namespace groundline::calibration {

const char* CameraFileFormatName(CameraFileFormat format) {
  switch (format) {
    case CameraFileFormat::kMrcalCameraModel:
      return "mrcal .cameramodel";
    case CameraFileFormat::kRosCameraInfo:
      return "ROS camera_info YAML";
    case CameraFileFormat::kOpenCvCalibration:
      return "OpenCV calibration file";
  }
  return "unknown";
}

core::Result<CameraFileFormat> DetectCameraFileFormat(const std::filesystem::path& path) {
  if (path.extension() == ".cameramodel") return CameraFileFormat::kMrcalCameraModel;
  core::Result<std::string> text = text_util::ReadTextFile(path, "camera intrinsics file");
  if (!text.ok()) return text.status();
  // A block-style top-level key: at the start of a line, unindented.
  static const std::regex kDistortionModelKey("(^|\n)\"?distortion_model\"?[ \t]*:");
  if (std::regex_search(*text, kDistortionModelKey)) return CameraFileFormat::kRosCameraInfo;
  return CameraFileFormat::kOpenCvCalibration;
}

core::Result<CameraModel> ReadCameraModel(const std::filesystem::path& path) {
  core::Result<CameraFileFormat> format = DetectCameraFileFormat(path);
  if (!format.ok()) return format.status();
  switch (*format) {
    case CameraFileFormat::kMrcalCameraModel: {
      core::Result<MrcalCameraModelFile> file = ReadMrcalCameraModel(path);
      if (!file.ok()) return file.status();
      return file->camera;
    }
    case CameraFileFormat::kRosCameraInfo: {
      core::Result<RosCameraInfo> info = ReadRosCameraInfo(path);
      if (!info.ok()) return info.status();
      return info->camera;
    }
    case CameraFileFormat::kOpenCvCalibration:
      break;
  }
  return ReadOpenCvCalibration(path);
}

}  // namespace groundline::calibration
