// The camera adapters on real devices; each test skips, saying why, on a
// machine without one (CI has none: the conversions they use are covered by
// pixel_conversion_test.cc).
#include <gtest/gtest.h>

#include <filesystem>

#include "groundline/io/frame_source.h"

namespace groundline::io {
namespace {

void ExpectFramesFrom(const std::string& uri) {
  core::Result<std::unique_ptr<FrameSource>> source = OpenFrameSource(uri);
  if (!source.ok()) GTEST_SKIP() << "cannot open " << uri << ": " << source.message();
  EXPECT_TRUE((*source)->IsLive());
  double last_stamp_s = -1.0;
  for (int i = 0; i < 3; ++i) {
    core::Result<std::optional<Frame>> frame = (*source)->Next(5.0);
    ASSERT_TRUE(frame.ok()) << frame.message();
    ASSERT_TRUE(frame->has_value()) << "a camera never ends";
    EXPECT_EQ((*frame)->grey.type(), CV_8UC1);
    EXPECT_GT((*frame)->grey.cols, 0);
    EXPECT_GT((*frame)->stamp_s, last_stamp_s);
    last_stamp_s = (*frame)->stamp_s;
  }
}

TEST(CaptureDevice, V4l2DeliversGreyFramesWithIncreasingStamps) {
  std::string device;
  std::error_code ec;
  for (int i = 0; i < 64 && device.empty(); ++i) {
    const std::string path = "/dev/video" + std::to_string(i);
    if (std::filesystem::exists(path, ec)) device = path;
  }
  if (device.empty()) GTEST_SKIP() << "no V4L2 device on this machine (/dev/video*)";
  ExpectFramesFrom("v4l2:" + device);
}

TEST(CaptureDevice, LibcameraDeliversGreyFramesWithIncreasingStamps) {
  core::Result<std::vector<std::string>> cameras = ListLibcameraCameras();
  if (!cameras.ok()) GTEST_SKIP() << cameras.message();
  if (cameras->empty()) GTEST_SKIP() << "libcamera finds no camera on this machine";
  ExpectFramesFrom("libcamera:0");
}

TEST(CaptureDevice, MissingDevicesAreErrorsNamingTheUri) {
  core::Result<std::unique_ptr<FrameSource>> v4l2 = OpenFrameSource("v4l2:/dev/no_such_video");
  ASSERT_FALSE(v4l2.ok());
  EXPECT_NE(v4l2.message().find("v4l2:/dev/no_such_video"), std::string::npos) << v4l2.message();
  EXPECT_NE(v4l2.message().find("cannot open"), std::string::npos) << v4l2.message();
  core::Result<std::unique_ptr<FrameSource>> cam = OpenFrameSource("libcamera:no-such-camera");
  ASSERT_FALSE(cam.ok());
  EXPECT_NE(cam.message().find("libcamera:no-such-camera"), std::string::npos) << cam.message();
}

}  // namespace
}  // namespace groundline::io
