// Image files decoded one after another into the same buffers.
//
// cv::imread allocates the decoded image afresh for every file: a stage that
// reads a frame per file for hours (the service replaying a dataset) then
// allocates and frees a frame-sized buffer per frame, which fragments a
// long-running process's heap (docs/service.md, "Memory"). GreyImageFileReader
// keeps the file's bytes and decodes into the caller's image, whose buffer
// cv::imdecode reuses when the size matches.
//
// Thread-safety: a reader is used from one thread.
#ifndef GROUNDLINE_IO_IMAGE_FILE_H_
#define GROUNDLINE_IO_IMAGE_FILE_H_

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::io {

class GreyImageFileReader {
 public:
  // The file's pixels as 8-bit grey in *grey (colour converted as cv::imread
  // does with IMREAD_GRAYSCALE). *grey's buffer is reused when it already has
  // the image's size and type, so a Mat sharing that buffer sees the new
  // pixels. Errors name the file: missing or unreadable, empty, or not a
  // decodable image (*grey is then empty).
  core::Status Read(const std::filesystem::path& path, cv::Mat* grey);

 private:
  std::vector<std::uint8_t> bytes_;
};

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_IMAGE_FILE_H_
