// Malformed intrinsics files give errors that name the file and the field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

struct BadFile {
  std::string name;
  std::string text;
  std::string expected;  // a piece of the error message
};

std::filesystem::path WriteText(const std::filesystem::path& dir, const std::string& name,
                                const std::string& text) {
  const std::filesystem::path path = dir / name;
  std::ofstream(path) << text;
  return path;
}

void ExpectErrors(const std::vector<BadFile>& files, const std::string& scratch) {
  const std::filesystem::path dir = groundline::testing::ScratchDir(scratch);
  for (const BadFile& file : files) {
    const std::filesystem::path path = WriteText(dir, file.name, file.text);
    core::Result<CameraModel> camera = ReadCameraModel(path);
    ASSERT_FALSE(camera.ok()) << file.name;
    EXPECT_NE(camera.message().find(file.name), std::string::npos) << camera.message();
    EXPECT_NE(camera.message().find(file.expected), std::string::npos)
        << file.name << ": " << camera.message();
  }
}

const char kOpenCvHeader[] = "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n";
const char kGoodK[] =
    "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
    "   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n";
std::string OpenCvD(int count) {
  std::string data;
  for (int i = 0; i < count; ++i) data += std::string(i ? ", " : "") + "0.001";
  return "distortion_coefficients: !!opencv-matrix\n   rows: " + std::to_string(count) +
         "\n   cols: 1\n   dt: d\n   data: [ " + data + " ]\n";
}

TEST(CameraFileErrors, OpenCvCalibration) {
  const std::string header = kOpenCvHeader;
  ExpectErrors(
      {
          {"no_k.yml", header + OpenCvD(5), "missing key 'camera_matrix'"},
          {"no_d.yml", header + kGoodK, "missing key 'distortion_coefficients'"},
          {"no_width.yml", std::string("%YAML:1.0\n---\nimage_height: 480\n") + kGoodK + OpenCvD(5),
           "missing key 'image_width'"},
          {"k_2x2.yml", header + "K: [ 500., 0., 0., 500. ]\n" + OpenCvD(5),
           "key 'K': expected a 3x3 matrix"},
          {"d_14.yml", header + kGoodK + OpenCvD(14), "tilted-sensor"},
          {"d_6.yml", header + kGoodK + OpenCvD(6), "expected 4, 5, 8 or 12 values"},
          {"negative_f.yml",
           header + "camera_matrix: [ -500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n" + OpenCvD(5),
           "focal lengths must be > 0"},
          {"skew.yml",
           header + "camera_matrix: [ 500., 0.5, 320., 0., 500., 240., 0., 0., 1. ]\n" + OpenCvD(5),
           "skew"},
          {"word.yml",
           header + "camera_matrix: [ abc, 0., 320., 0., 500., 240., 0., 0., 1. ]\n" + OpenCvD(5),
           "element 0 is not a number"},
          // Read by yaml-cpp (not OpenCV's YAML parser, which can hang): the line is named.
          {"syntax.yml", "%YAML:1.0\n---\ncamera_matrix: [ 1, 2\n", ":4: YAML syntax error"},
      },
      "opencv");
}

const char kInfoTail[] =
    "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"
    "projection_matrix:\n  rows: 3\n  cols: 4\n  data: [500, 0, 320, 0, 0, 500, 240, 0, 0, 0, 1, "
    "0]\n";
std::string Info(const std::string& k_data, const std::string& model, const std::string& d_data,
                 int d_cols) {
  return "image_width: 640\nimage_height: 480\ncamera_name: test\n"
         "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [" +
         k_data +
         "]\n"
         "distortion_model: " +
         model +
         "\n"
         "distortion_coefficients:\n  rows: 1\n  cols: " +
         std::to_string(d_cols) + "\n  data: [" + d_data + "]\n" + kInfoTail;
}

TEST(CameraFileErrors, RosCameraInfo) {
  const std::string k = "500, 0, 320, 0, 500, 240, 0, 0, 1";
  const std::string d5 = "-0.2, 0.05, 0.001, 0.001, 0";
  ASSERT_TRUE(ParseRosCameraInfo(Info(k, "plumb_bob", d5, 5), "good").ok());
  std::string no_height = Info(k, "plumb_bob", d5, 5);
  no_height.erase(no_height.find("image_height"), std::string("image_height: 480\n").size());
  ExpectErrors(
      {
          {"no_height.yaml", no_height, "missing key 'image_height'"},
          {"k8.yaml", Info("500, 0, 320, 0, 500, 240, 0, 0", "plumb_bob", d5, 5),
           ":4: key 'camera_matrix': expected 9 numbers in 'data', got 8"},
          {"model.yaml", Info(k, "foo", d5, 5), "expected plumb_bob or rational_polynomial"},
          {"fisheye.yaml", Info(k, "equidistant", "0.1, 0.01, 0, 0", 4), "Kannala-Brandt"},
          {"count.yaml", Info(k, "plumb_bob", d5 + ", 0, 0, 0", 8), "got 1x8"},
          {"word.yaml", Info(k, "plumb_bob", "-0.2, 0.05, abc, 0.001, 0", 5),
           "data[2]: expected a finite number, got 'abc'"},
          {"negative_f.yaml", Info("-500, 0, 320, 0, 500, 240, 0, 0, 1", "plumb_bob", d5, 5),
           "focal lengths must be > 0"},
      },
      "camera_info");
}

TEST(CameraFileErrors, MrcalCameraModel) {
  const std::string body =
      "'lensmodel': 'LENSMODEL_OPENCV4', 'intrinsics': [500, 500, 320, 240, 0, 0, 0, 0], ";
  ExpectErrors(
      {
          {"no_size.cameramodel", "{" + body + "'extrinsics': [0, 0, 0, 0, 0, 0] }",
           "missing key 'imagersize'"},
          {"garbage.cameramodel",
           "{" + body + "'extrinsics': [0, 0, 0, 0, 0, 0], 'imagersize': [640, 480 }",
           "parser rejected"},
          {"count.cameramodel",
           "{ 'lensmodel': 'LENSMODEL_OPENCV4', 'intrinsics': [500, 500, 320, 240], "
           "'extrinsics': [0, 0, 0, 0, 0, 0], 'imagersize': [640, 480] }",
           "rejected"},
          {"negative_f.cameramodel",
           "{ 'lensmodel': 'LENSMODEL_PINHOLE', 'intrinsics': [500, -500, 320, 240], "
           "'extrinsics': [0, 0, 0, 0, 0, 0], 'imagersize': [640, 480] }",
           "focal lengths must be > 0"},
          {"cahvore.cameramodel",
           "{ 'lensmodel': 'LENSMODEL_CAHVORE_linearity=0.00', 'intrinsics': [500, 500, 320, 240, "
           "0, 0, 0, 0, 0, 0, 0, 0], 'extrinsics': [0, 0, 0, 0, 0, 0], 'imagersize': [640, 480] }",
           "CAHVORE"},
      },
      "cameramodel");
}

}  // namespace
}  // namespace groundline::calibration
