// The capture adapters' pixel conversions on synthetic buffers (no camera).
#include "groundline/io/pixel_conversion.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <vector>

namespace groundline::io {
namespace {

std::uint8_t Luma(int u, int v) { return static_cast<std::uint8_t>((7 * u + 13 * v) % 256); }

TEST(PixelConversion, YuyvKeepsTheLumaBytesAndHonoursTheStride) {
  const int width = 6, height = 3, stride = 2 * width + 4;  // 4 bytes of row padding
  std::vector<std::uint8_t> buffer(static_cast<std::size_t>(stride) * height, 0xEE);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      buffer[v * stride + 2 * u] = Luma(u, v);
      buffer[v * stride + 2 * u + 1] = static_cast<std::uint8_t>(u % 2 == 0 ? 90 : 160);  // U, V
    }
  }
  core::Result<cv::Mat> grey =
      ConvertToGrey(PixelFormat::kYuyv, buffer.data(), buffer.size(), width, height, stride);
  ASSERT_TRUE(grey.ok()) << grey.message();
  ASSERT_EQ(grey->type(), CV_8UC1);
  ASSERT_EQ(grey->size(), cv::Size(width, height));
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) EXPECT_EQ(grey->at<std::uint8_t>(v, u), Luma(u, v));
  }
  buffer[0] = 1;  // the result owns its pixels
  EXPECT_EQ(grey->at<std::uint8_t>(0, 0), Luma(0, 0));
}

TEST(PixelConversion, GreyAndLumaPlaneCopyTheFirstRows) {
  const int width = 5, height = 4, stride = 8;
  // NV12: the luma plane, then half as many rows of interleaved chroma.
  std::vector<std::uint8_t> nv12(static_cast<std::size_t>(stride) * height * 3 / 2, 128);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) nv12[v * stride + u] = Luma(u, v);
  }
  for (PixelFormat f : {PixelFormat::kGrey, PixelFormat::kLumaPlane}) {
    core::Result<cv::Mat> grey = ConvertToGrey(f, nv12.data(), nv12.size(), width, height, stride);
    ASSERT_TRUE(grey.ok()) << grey.message();
    for (int v = 0; v < height; ++v) {
      for (int u = 0; u < width; ++u) EXPECT_EQ(grey->at<std::uint8_t>(v, u), Luma(u, v));
    }
  }
}

TEST(PixelConversion, TruncatedBufferIsAnErrorNamingTheSizes) {
  std::vector<std::uint8_t> buffer(2 * 6 * 3 - 1, 0);
  core::Result<cv::Mat> grey =
      ConvertToGrey(PixelFormat::kYuyv, buffer.data(), buffer.size(), 6, 3, 12);
  ASSERT_FALSE(grey.ok());
  EXPECT_NE(grey.message().find("truncated YUYV frame 6x3 (stride 12 bytes) in 35 bytes"),
            std::string::npos)
      << grey.message();
}

TEST(PixelConversion, MjpegDecodesToGreyAndRejectsGarbageAndWrongSize) {
  cv::Mat bgr(24, 32, CV_8UC3, cv::Scalar(0, 0, 0));
  bgr(cv::Rect(16, 0, 16, 24)).setTo(cv::Scalar(255, 255, 255));
  std::vector<std::uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
  core::Result<cv::Mat> grey =
      ConvertToGrey(PixelFormat::kMjpeg, jpeg.data(), jpeg.size(), 32, 24, 0);
  ASSERT_TRUE(grey.ok()) << grey.message();
  ASSERT_EQ(grey->type(), CV_8UC1);
  EXPECT_LE(grey->at<std::uint8_t>(12, 4), 8);     // black half
  EXPECT_GE(grey->at<std::uint8_t>(12, 28), 247);  // white half

  core::Result<cv::Mat> wrong =
      ConvertToGrey(PixelFormat::kMjpeg, jpeg.data(), jpeg.size(), 64, 48, 0);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.message().find("decodes to 32x24, expected 64x48"), std::string::npos)
      << wrong.message();
  std::vector<std::uint8_t> garbage(jpeg.begin(), jpeg.begin() + 20);
  core::Result<cv::Mat> bad =
      ConvertToGrey(PixelFormat::kMjpeg, garbage.data(), garbage.size(), 32, 24, 0);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("does not decode"), std::string::npos) << bad.message();
}

}  // namespace
}  // namespace groundline::io
