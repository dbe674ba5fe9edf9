// Inputs that fuzzing found to crash or throw out of a calibration reader
// (their bytes are also in fuzz/corpus/*/regress_*): each must now come back
// as an error, or a result, with a message that names the source and the key.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/camera_mount_yaml.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/mrcal_cameramodel_io.h"
#include "groundline/calibration/opencv_calibration_io.h"
#include "groundline/calibration/ros_camera_info_io.h"
#include "groundline/calibration/tag_layout.h"
#include "test_data.h"

namespace groundline::calibration {
namespace {

constexpr char kPinhole[] =
    "{\n"
    "    'lensmodel':  'LENSMODEL_PINHOLE',\n"
    "    'intrinsics': [ 600, 600, 639.5, 399.5,],\n"
    "    'extrinsics': [ 0, 0, 0, 0, 0, 0,],\n"
    "    'imagersize': [ 1280, 800,],\n"
    "}\n";

// libmrcal's parser read past the end of a text that ends inside a comment.
TEST(ReaderHardening, CameraModelEndingInACommentWithoutNewlineParses) {
  const auto model = ParseMrcalCameraModel(std::string(kPinhole) + "# a last comment", "a");
  ASSERT_TRUE(model.ok()) << model.message();
  EXPECT_EQ(model->camera.width_px(), 1280);
  std::string zero_height(kPinhole);
  zero_height.replace(zero_height.find("1280, 800"), 9, "1280, 0");
  const auto broken = ParseMrcalCameraModel(zero_height + "#lens\0\0mo", "b.cameramodel");
  ASSERT_FALSE(broken.ok());
  EXPECT_NE(broken.message().find("b.cameramodel: key 'imagersize'"), std::string::npos)
      << broken.message();
}

// libmrcal's lexer read past the end of a text with an unterminated string.
TEST(ReaderHardening, CameraModelWithAnUnterminatedStringIsRejectedBeforeMrcal) {
  const std::string text(kPinhole);
  for (const auto& [bad, expected] : {
           std::pair<std::string, std::string>{text.substr(0, text.size() - 2) + " 'intrin",
                                               "line 6: a string that is never closed"},
           {text.substr(0, text.size() - 2) + " \"abc\n", "line 6: a string that is never closed"},
           {text + std::string("\0", 1), "line 7: a NUL byte"},
       }) {
    const auto model = ParseMrcalCameraModel(bad, "c.cameramodel");
    ASSERT_FALSE(model.ok()) << bad;
    EXPECT_NE(model.message().find("c.cameramodel: " + expected), std::string::npos)
        << model.message();
  }
  // Quotes inside a comment open no string.
  EXPECT_TRUE(ParseMrcalCameraModel("# it's mrcal's\n" + text, "d").ok());
}

// OpenCV allocated rows x cols before reading 'data': a damaged header asked
// for gigabytes.
TEST(ReaderHardening, OpenCvMatrixSizesAreCheckedBeforeOpenCvAllocates) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("opencv");
  const std::string head = "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n";
  const std::string d =
      "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
      "   data: [ -0.28, 0.03, 0.001, 0.0, 0.1 ]\n";
  for (const auto& [rows_cols, expected] :
       {std::pair<std::string, std::string>{"rows: 3000000\n   cols: 3000000", "'rows' and 'cols'"},
        {"rows: 3\n   cols: z", "'rows' and 'cols'"},
        {"rows: 4\n   cols: 3", "rows x cols = 12 numbers, got 9"}}) {
    const std::filesystem::path path = dir / "camera.yaml";
    std::ofstream(path) << head << "camera_matrix: !!opencv-matrix\n   " << rows_cols
                        << "\n   dt: d\n   data: [ 532.8, 0., 342.5, 0., 532.9, 233.9, 0., 0., "
                           "1. ]\n"
                        << d;
    const auto camera = ReadOpenCvCalibration(path);
    ASSERT_FALSE(camera.ok()) << rows_cols;
    EXPECT_NE(camera.message().find(path.string() + ": key 'camera_matrix'"), std::string::npos)
        << camera.message();
    EXPECT_NE(camera.message().find(expected), std::string::npos) << camera.message();
  }
}

// cv::FileStorage's operator[] asserted (threw) on a document that is not a mapping.
TEST(ReaderHardening, OpenCvDocumentThatIsNotAMappingIsAnError) {
  const std::filesystem::path path = ::groundline::testing::ScratchDir("opencv_root") / "camera.yaml";
  std::ofstream(path) << "%YAML:1.0\n---\n- 1\n- 2\n";
  const auto camera = ReadOpenCvCalibration(path);
  ASSERT_FALSE(camera.ok());
  EXPECT_NE(camera.message().find(path.string() + ": expected a mapping"), std::string::npos)
      << camera.message();
}

// yaml-cpp threw BadSubscript (operator[] on a scalar) out of the readers
// when a document was not the mapping they walk.
TEST(ReaderHardening, YamlReadersReturnAnErrorForAScalarOrListDocument) {
  for (const char* text : {"just a scalar\n", "- a\n- b\n", "[1, {x: 2}]\n"}) {
    const auto targets = ParseCalibTargets(text, "targets.yaml");
    ASSERT_FALSE(targets.ok()) << text;
    EXPECT_NE(targets.message().find("targets.yaml"), std::string::npos) << targets.message();
    EXPECT_FALSE(ParseTagLayoutYaml(text, "layout.yaml").ok()) << text;
    EXPECT_FALSE(ParseCameraMountYaml(text, "extrinsics.yaml").ok()) << text;
    EXPECT_FALSE(ParseRosCameraInfo(text, "camera_info.yaml").ok()) << text;
  }
}

// nlohmann's value() threw type_error out of the reader for a 'format' that
// is not a string.
TEST(ReaderHardening, IntrinsicsReportWithANonStringFormatIsAnError) {
  const std::filesystem::path path = ::groundline::testing::ScratchDir("report") / "report.json";
  for (const char* text : {R"({"format": 3})", R"([1, 2])", R"({"format": null})"}) {
    std::ofstream(path) << text;
    const auto summary = ReadIntrinsicsReportSummary(path);
    ASSERT_FALSE(summary.ok()) << text;
    EXPECT_NE(summary.message().find(path.string() + ": field 'format'"), std::string::npos)
        << summary.message();
  }
}

}  // namespace
}  // namespace groundline::calibration
