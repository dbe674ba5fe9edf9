#include "groundline/io/image_file.h"

#include <cassert>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <string>

namespace groundline::io {

core::Status GreyImageFileReader::Read(const std::filesystem::path& path, cv::Mat* grey) {
  assert(grey != nullptr);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    grey->release();
    return core::Status::Error(path.string() + ": cannot be opened (expected an image file)");
  }
  const std::streamoff size = in.tellg();
  if (size <= 0) {
    grey->release();
    return core::Status::Error(path.string() + ": empty file (expected an image)");
  }
  if (size > std::numeric_limits<int>::max()) {
    grey->release();
    return core::Status::Error(path.string() + ": " + std::to_string(size) +
                               " bytes, more than an image file can hold here (2 GB)");
  }
  bytes_.resize(static_cast<std::size_t>(size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes_.data()), size)) {
    grey->release();
    return core::Status::Error(path.string() + ": read failed after " +
                               std::to_string(in.gcount()) + " of " + std::to_string(size) +
                               " bytes");
  }
  // cv::imdecode leaves *grey untouched when no decoder takes the bytes or
  // their header is broken, and returns it all the same: the previous file's
  // pixels could pass for this one's. So the buffer is zeroed first, and an
  // all-zero result is confirmed by a decode into a fresh image (a black frame
  // is rare; that one allocates).
  const cv::Mat buffer(1, static_cast<int>(size), CV_8UC1, bytes_.data());
  try {
    if (!grey->empty()) grey->setTo(0);
    cv::imdecode(buffer, cv::IMREAD_GRAYSCALE, grey);
    if (!grey->empty() && cv::countNonZero(*grey) == 0) {
      *grey = cv::imdecode(buffer, cv::IMREAD_GRAYSCALE);
    }
  } catch (const cv::Exception& e) {
    grey->release();
    return core::Status::Error(path.string() + ": cannot be decoded as an image (" + e.what() +
                               ")");
  }
  if (grey->empty()) {
    return core::Status::Error(path.string() + ": cannot be decoded as an image");
  }
  return core::Status::Ok();
}

}  // namespace groundline::io
