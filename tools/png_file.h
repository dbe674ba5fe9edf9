// Writing a PNG the way every other output is written: encoded in memory
// (cv::imencode), then through core::WriteFileAtomically, so a reader (or a
// run killed half-way) never leaves a torn image under the final name.
#ifndef GROUNDLINE_TOOLS_PNG_FILE_H_
#define GROUNDLINE_TOOLS_PNG_FILE_H_

#include <filesystem>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "groundline/core/atomic_file.h"
#include "groundline/core/status.h"

namespace groundline::tools {

// Errors name the file: the image cannot be encoded (empty, unsupported
// depth) or the file cannot be written.
inline core::Status WritePngAtomically(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<unsigned char> png;
  if (image.empty() || !cv::imencode(".png", image, png)) {
    return core::Status::Error(path.string() + ": cannot encode the image as PNG");
  }
  return core::WriteFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_PNG_FILE_H_
