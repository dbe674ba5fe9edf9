#include "png_data_uri.h"

#include <cassert>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace groundline::calibration::internal {

std::string Base64(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = static_cast<std::uint32_t>(bytes[i]) << 16;
    if (n > 1) v |= static_cast<std::uint32_t>(bytes[i + 1]) << 8;
    if (n > 2) v |= bytes[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += n > 1 ? kAlphabet[(v >> 6) & 63] : '=';
    out += n > 2 ? kAlphabet[v & 63] : '=';
  }
  return out;
}

std::string GreyPngDataUri(const std::vector<std::uint8_t>& grey, int width_px, int height_px) {
  assert(grey.size() == static_cast<std::size_t>(width_px) * height_px);
  const cv::Mat image(height_px, width_px, CV_8UC1, const_cast<std::uint8_t*>(grey.data()));
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", image, png)) return "";
  return "data:image/png;base64," + Base64(png);
}

}  // namespace groundline::calibration::internal
