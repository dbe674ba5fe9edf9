#include "groundline/io/pixel_conversion.h"

#include <algorithm>
#include <cassert>
#include <opencv2/imgcodecs.hpp>
#include <vector>

namespace groundline::io {
namespace {

std::string Sizes(PixelFormat format, std::size_t bytes, int width_px, int height_px,
                  int stride_bytes) {
  return std::string(PixelFormatName(format)) + " frame " + std::to_string(width_px) + "x" +
         std::to_string(height_px) + " (stride " + std::to_string(stride_bytes) + " bytes) in " +
         std::to_string(bytes) + " bytes";
}

}  // namespace

const char* PixelFormatName(PixelFormat format) {
  switch (format) {
    case PixelFormat::kGrey:
      return "GREY";
    case PixelFormat::kYuyv:
      return "YUYV";
    case PixelFormat::kLumaPlane:
      return "Y-plane";
    case PixelFormat::kMjpeg:
      return "MJPG";
  }
  return "?";
}

core::Result<cv::Mat> ConvertToGrey(PixelFormat format, const std::uint8_t* data, std::size_t bytes,
                                    int width_px, int height_px, int stride_bytes) {
  assert(data != nullptr || bytes == 0);
  if (format == PixelFormat::kMjpeg) {
    if (bytes == 0) return core::Status::Error("empty MJPG frame");
    const cv::Mat encoded(1, static_cast<int>(bytes), CV_8UC1, const_cast<std::uint8_t*>(data));
    cv::Mat grey = cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) {
      return core::Status::Error("MJPG frame of " + std::to_string(bytes) +
                                 " bytes does not decode as a JPEG");
    }
    if ((width_px > 0 && grey.cols != width_px) || (height_px > 0 && grey.rows != height_px)) {
      return core::Status::Error("MJPG frame decodes to " + std::to_string(grey.cols) + "x" +
                                 std::to_string(grey.rows) + ", expected " +
                                 std::to_string(width_px) + "x" + std::to_string(height_px));
    }
    return grey;
  }
  assert(width_px > 0 && height_px > 0);
  const int bytes_per_pixel = format == PixelFormat::kYuyv ? 2 : 1;
  const std::size_t row_bytes = static_cast<std::size_t>(width_px) * bytes_per_pixel;
  if (stride_bytes < static_cast<int>(row_bytes) ||
      bytes < static_cast<std::size_t>(stride_bytes) * (height_px - 1) + row_bytes) {
    return core::Status::Error("truncated " +
                               Sizes(format, bytes, width_px, height_px, stride_bytes));
  }
  cv::Mat grey(height_px, width_px, CV_8UC1);
  for (int v = 0; v < height_px; ++v) {
    const std::uint8_t* row = data + static_cast<std::size_t>(v) * stride_bytes;
    std::uint8_t* out = grey.ptr<std::uint8_t>(v);
    if (format == PixelFormat::kYuyv) {
      for (int u = 0; u < width_px; ++u) out[u] = row[2 * u];
    } else {
      std::copy(row, row + width_px, out);
    }
  }
  return grey;
}

}  // namespace groundline::io
