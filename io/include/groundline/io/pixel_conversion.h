// Camera pixel formats to the 8-bit grey frames of frame_source.h. Pure
// functions on memory buffers, so that the capture adapters' conversions are
// tested without a camera. Each copies: the result never aliases the input
// (driver buffers are returned to the driver right after conversion).
//
// Layouts (V4L2 names; libcamera's formats of the same memory layout map to
// them):
//   GREY  (V4L2_PIX_FMT_GREY, libcamera R8): one byte per pixel.
//   YUYV  (V4L2_PIX_FMT_YUYV, libcamera YUYV): Y0 U Y1 V per two pixels; the
//         grey image is the luma Y (BT.601 studio or full range as sent).
//   Y plane first (libcamera YUV420, NV12, NV21; V4L2 YU12, NV12): the first
//         height rows of the plane are the luma; only they are read.
//   MJPG  (V4L2_PIX_FMT_MJPEG, libcamera MJPEG): one JPEG per frame, decoded
//         by OpenCV's imdecode to grey.
// stride_bytes is the distance between row starts (>= the row's payload).
#ifndef GROUNDLINE_IO_PIXEL_CONVERSION_H_
#define GROUNDLINE_IO_PIXEL_CONVERSION_H_

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "groundline/core/status.h"

namespace groundline::io {

enum class PixelFormat { kGrey, kYuyv, kLumaPlane, kMjpeg };

// "GREY", "YUYV", "Y-plane", "MJPG".
const char* PixelFormatName(PixelFormat format);

// Converts one frame. Fails, naming the format and the sizes, when the buffer
// is shorter than the layout needs (a truncated frame), or when an MJPEG frame
// does not decode or decodes to another size than width x height (for MJPEG,
// width/height 0 accept any size).
core::Result<cv::Mat> ConvertToGrey(PixelFormat format, const std::uint8_t* data, std::size_t bytes,
                                    int width_px, int height_px, int stride_bytes);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_PIXEL_CONVERSION_H_
