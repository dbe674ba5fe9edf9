// Camera intrinsics files: write then read back at full precision, the real
// files in ../shared/data, and the ReadCameraModel dispatch.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "groundline/calibration/camera_file.h"
#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "mrcal_adapter.h"  // to read our .cameramodel files with mrcal's own C reader
#include "test_cameras.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

using test_cameras::AllTestCameras;
using test_cameras::MakeCamera;

// Values that do not survive six decimals (mrcal_write_cameramodel_file's %f).
CameraModel PreciseOpenCv8() {
  return MakeCamera("LENSMODEL_OPENCV8",
                    {531.123456789012345, 530.987654321098765, 322.000000000001, 241.91919191919191,
                     -0.310000000000003, 0.12345678901234567, 1.23456789e-5, -7.0e-7, 0.02, 0.05,
                     0.011, 2.5e-17});
}

void ExpectSameCamera(const CameraModel& a, const CameraModel& b) {
  EXPECT_EQ(a.lens_model(), b.lens_model());
  EXPECT_EQ(a.width_px(), b.width_px());
  EXPECT_EQ(a.height_px(), b.height_px());
  EXPECT_EQ(a.intrinsics(), b.intrinsics());  // bit for bit
}

TEST(MrcalCameraModelIo, WritesAndReadsBackEveryModelExactly) {
  const std::filesystem::path dir = groundline::testing::ScratchDir("cameramodel");
  std::vector<CameraModel> cameras = AllTestCameras();
  cameras.push_back(PreciseOpenCv8());
  const std::array<double, 6> rt_cam_ref = {0.1, -0.2, 0.30000000000000004, 1.5, -2.25, 1e-9};
  for (size_t i = 0; i < cameras.size(); ++i) {
    const std::filesystem::path path = dir / ("camera" + std::to_string(i) + ".cameramodel");
    ASSERT_TRUE(WriteMrcalCameraModel(path, cameras[i], rt_cam_ref).ok());
    core::Result<MrcalCameraModelFile> read = ReadMrcalCameraModel(path);
    ASSERT_TRUE(read.ok()) << read.message();
    ExpectSameCamera(read->camera, cameras[i]);
    EXPECT_EQ(read->rt_cam_ref, rt_cam_ref);

    // mrcal's own file reader, independently of groundline's reading path.
    const mrcal_adapter::CameraModelPtr raw = mrcal_adapter::ReadCameraModelFile(path);
    ASSERT_NE(raw, nullptr) << path;
    for (size_t k = 0; k < cameras[i].intrinsics().size(); ++k) {
      EXPECT_EQ(raw->intrinsics[k], cameras[i].intrinsics()[k]);
    }
    EXPECT_EQ(raw->imagersize[0], 640u);
    EXPECT_EQ(raw->rt_cam_ref[2], rt_cam_ref[2]);
  }
}

TEST(OpenCvCalibrationIo, WritesAndReadsBackOpenCvModelsExactly) {
  const std::filesystem::path dir = groundline::testing::ScratchDir("opencv");
  int written = 0;
  std::vector<CameraModel> cameras = AllTestCameras();
  cameras.push_back(PreciseOpenCv8());
  for (const CameraModel& camera : cameras) {
    const std::filesystem::path path = dir / ("camera" + std::to_string(written) + ".yml");
    const core::Status status = WriteOpenCvCalibration(path, camera);
    const bool representable =
        camera.family() == LensFamily::kPinhole || camera.family() == LensFamily::kOpenCv4 ||
        camera.family() == LensFamily::kOpenCv5 || camera.family() == LensFamily::kOpenCv8 ||
        camera.family() == LensFamily::kOpenCv12;
    ASSERT_EQ(status.ok(), representable) << camera.lens_model() << ": " << status.message();
    if (!representable) {
      EXPECT_NE(status.message().find("no OpenCV equivalent"), std::string::npos);
      EXPECT_FALSE(std::filesystem::exists(path));
      continue;
    }
    ++written;
    core::Result<CameraModel> read = ReadOpenCvCalibration(path);
    ASSERT_TRUE(read.ok()) << read.message();
    if (camera.family() == LensFamily::kPinhole) {
      EXPECT_EQ(read->lens_model(), "LENSMODEL_OPENCV5");  // zero distortion, same projection
      EXPECT_EQ(std::vector<double>(read->intrinsics().begin(), read->intrinsics().begin() + 4),
                camera.intrinsics());
    } else {
      ExpectSameCamera(*read, camera);
    }
  }
  EXPECT_EQ(written, 6);
}

TEST(RosCameraInfoIo, WritesAndReadsBackExactly) {
  const std::filesystem::path dir = groundline::testing::ScratchDir("camera_info");
  for (const CameraModel& camera : {PreciseOpenCv8(), AllTestCameras()[3], AllTestCameras()[2]}) {
    RosCameraInfo info = MakeRosCameraInfo(camera, "front \"left\"");
    info.projection(0, 3) = -38.75;  // a stereo baseline term
    info.rectification =
        Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.3, 0.1, 1.0).normalized()).toRotationMatrix();
    const std::filesystem::path path = dir / "info.yaml";
    ASSERT_TRUE(WriteRosCameraInfo(path, info).ok());
    core::Result<RosCameraInfo> read = ReadRosCameraInfo(path);
    ASSERT_TRUE(read.ok()) << read.message();
    EXPECT_EQ(read->camera_name, "front \"left\"");
    EXPECT_EQ(read->rectification, info.rectification);
    EXPECT_EQ(read->projection, info.projection);
    if (camera.family() == LensFamily::kOpenCv4) {
      EXPECT_EQ(read->camera.lens_model(), "LENSMODEL_OPENCV5");  // plumb_bob with k3 = 0
      EXPECT_EQ(read->camera.intrinsics().back(), 0.0);
    } else {
      ExpectSameCamera(read->camera, camera);
    }
  }
  const RosCameraInfo splined = MakeRosCameraInfo(AllTestCameras()[7], "wide");
  EXPECT_FALSE(RosCameraInfoToYaml(splined).ok());
}

TEST(RealCameraFiles, OpenCvReferenceLeftIntrinsics) {
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left_intrinsics.reference.yml");
  const std::filesystem::path path = groundline::testing::SharedDataDir() /
                                     "calib/opencv_chessboard/left_intrinsics.reference.yml";
  core::Result<CameraFileFormat> format = DetectCameraFileFormat(path);
  ASSERT_TRUE(format.ok());
  EXPECT_EQ(*format, CameraFileFormat::kOpenCvCalibration);
  core::Result<CameraModel> camera = ReadCameraModel(path);
  ASSERT_TRUE(camera.ok()) << camera.message();
  EXPECT_EQ(camera->lens_model(), "LENSMODEL_OPENCV5");
  EXPECT_EQ(camera->width_px(), 640);
  EXPECT_EQ(camera->height_px(), 480);
  EXPECT_NEAR(camera->intrinsics()[0], 535.916, 1e-3);
  EXPECT_EQ(camera->intrinsics()[0], 5.3591573396163199e+02);
  EXPECT_NEAR(camera->intrinsics()[2], 342.283, 1e-3);
  EXPECT_NEAR(camera->intrinsics()[3], 235.571, 1e-3);
  EXPECT_NEAR(camera->intrinsics()[4], -0.26637, 1e-5);
  EXPECT_NEAR(camera->intrinsics()[8], 0.23839, 1e-5);
}

TEST(RealCameraFiles, DuckietownCameraInfoFiles) {
  GROUNDLINE_REQUIRE_DATA("floor/duckietown");
  const std::filesystem::path root = groundline::testing::SharedDataDir() / "floor/duckietown";
  for (const char* name : {"extrinsics/dd24/real-world/scenario0/calibration-intrinsic-dd24.yaml",
                           "robot_calibrations/camera_intrinsic/default.yaml",
                           "robot_calibrations/camera_intrinsic/milo.yaml",
                           "robot_calibrations/camera_intrinsic/tori.yaml"}) {
    const std::filesystem::path path = root / name;
    core::Result<CameraFileFormat> format = DetectCameraFileFormat(path);
    ASSERT_TRUE(format.ok()) << format.message();
    EXPECT_EQ(*format, CameraFileFormat::kRosCameraInfo) << name;
    core::Result<RosCameraInfo> info = ReadRosCameraInfo(path);
    ASSERT_TRUE(info.ok()) << info.message();
    EXPECT_EQ(info->camera.lens_model(), "LENSMODEL_OPENCV5");
    EXPECT_GT(info->camera.intrinsics()[0], 250.0);
    EXPECT_LT(info->camera.intrinsics()[0], 400.0);
    EXPECT_LT(info->camera.intrinsics()[4], -0.2);  // strong barrel distortion
  }
  core::Result<RosCameraInfo> dd24 = ReadRosCameraInfo(
      root / "extrinsics/dd24/real-world/scenario0/calibration-intrinsic-dd24.yaml");
  ASSERT_TRUE(dd24.ok());
  EXPECT_EQ(dd24->camera.width_px(), 480);  // portrait
  EXPECT_EQ(dd24->camera.height_px(), 640);
  EXPECT_EQ(dd24->camera.intrinsics()[0], 309.1791995555939);
  EXPECT_EQ(dd24->camera_name, "dd24_480_640");
  core::Result<RosCameraInfo> milo =
      ReadRosCameraInfo(root / "robot_calibrations/camera_intrinsic/milo.yaml");
  ASSERT_TRUE(milo.ok());
  EXPECT_EQ(milo->camera.width_px(), 640);
  EXPECT_EQ(milo->projection(0, 0), 208.1746063232422);
  EXPECT_EQ(milo->camera_name, "milo/camera_node");
}

TEST(ReadCameraModel, DispatchesOnExtensionAndContent) {
  const std::filesystem::path dir = groundline::testing::ScratchDir("dispatch");
  const CameraModel camera = PreciseOpenCv8();
  ASSERT_TRUE(WriteMrcalCameraModel(dir / "a.cameramodel", camera).ok());
  ASSERT_TRUE(WriteOpenCvCalibration(dir / "b.yaml", camera).ok());
  ASSERT_TRUE(WriteRosCameraInfo(dir / "c.yaml", MakeRosCameraInfo(camera, "c")).ok());
  const std::vector<std::pair<std::string, CameraFileFormat>> files = {
      {"a.cameramodel", CameraFileFormat::kMrcalCameraModel},
      {"b.yaml", CameraFileFormat::kOpenCvCalibration},
      {"c.yaml", CameraFileFormat::kRosCameraInfo}};
  for (const auto& [name, expected] : files) {
    EXPECT_EQ(*DetectCameraFileFormat(dir / name), expected) << name;
    core::Result<CameraModel> read = ReadCameraModel(dir / name);
    ASSERT_TRUE(read.ok()) << name << ": " << read.message();
    ExpectSameCamera(*read, camera);
  }
  core::Result<CameraModel> missing = ReadCameraModel(dir / "none.yaml");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("none.yaml"), std::string::npos);
}

}  // namespace
}  // namespace groundline::calibration
