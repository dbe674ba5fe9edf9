#include "folder_frame_source.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "groundline/core/dataset_records.h"
#include "groundline/io/image_file.h"

namespace groundline::io {
namespace {

namespace fs = std::filesystem;

struct FolderEntry {
  fs::path path;
  double stamp_s = 0.0;
};

class FolderFrameSource final : public FrameSource {
 public:
  FolderFrameSource(std::string description, std::vector<FolderEntry> entries)
      : description_(std::move(description)), entries_(std::move(entries)) {}

  core::Result<std::optional<Frame>> Next(double /*timeout_s*/) override {
    while (next_ < entries_.size()) {
      const FolderEntry& entry = entries_[next_++];
      // A fresh image per frame: the frame is handed on and may outlive the
      // next one. The reader keeps the file buffer and says what is wrong.
      cv::Mat grey;
      if (core::Status read = reader_.Read(entry.path, &grey); !read.ok()) {
        ++stats_.skipped;
        stats_.skipped_reasons.push_back(read.message() + "; skipped");
        continue;
      }
      Frame frame;
      frame.grey = std::move(grey);
      frame.stamp_s = entry.stamp_s;
      frame.sequence = stats_.delivered++;
      frame.name = entry.path.filename().string();
      return std::optional<Frame>(std::move(frame));
    }
    return std::optional<Frame>();
  }
  std::string Describe() const override { return description_; }
  bool IsLive() const override { return false; }
  const FrameSourceStats& stats() const override { return stats_; }

 private:
  std::string description_;
  std::vector<FolderEntry> entries_;
  std::size_t next_ = 0;
  GreyImageFileReader reader_;
  FrameSourceStats stats_;
};

// The image index of a dataset image directory, when there is one.
std::optional<fs::path> FindImageIndex(const fs::path& dir) {
  std::error_code ec;
  for (const fs::path& candidate : {dir / "index.csv", dir / "images" / "index.csv"}) {
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  return std::nullopt;
}

}  // namespace

core::Result<std::unique_ptr<FrameSource>> OpenFolderFrameSource(const std::string& uri,
                                                                 const FrameSourceUri& parsed) {
  std::vector<FolderEntry> entries;
  std::error_code ec;
  std::string stamps;
  const fs::path location(parsed.location);
  if (fs::is_directory(location, ec)) {
    if (const std::optional<fs::path> index = FindImageIndex(location)) {
      core::Result<std::vector<core::ImageRecord>> records = core::ReadImageIndex(*index);
      if (!records.ok()) return records.status().WithContext(uri);
      for (const core::ImageRecord& r : *records) {
        entries.push_back({index->parent_path() / r.file, r.stamp_s});
      }
      stamps = "stamps from " + index->string();
    }
  } else if (!fs::exists(location.has_parent_path() ? location.parent_path() : fs::path("."), ec)) {
    return core::Status::Error(uri + ": no such directory '" + parsed.location +
                               "' (expected a directory of images or a glob on file names)");
  }
  if (entries.empty()) {
    const std::vector<std::string> files = ListImageFiles(parsed.location);
    for (std::size_t i = 0; i < files.size(); ++i) {
      entries.push_back({files[i], static_cast<double>(i) / parsed.options.folder_rate_hz});
    }
    char rate[64];
    std::snprintf(rate, sizeof(rate), "stamps at %g Hz", parsed.options.folder_rate_hz);
    stamps = rate;
  }
  if (entries.empty()) {
    return core::Status::Error(uri + ": no image file (.png .jpg .jpeg .bmp .pgm .tif) in '" +
                               parsed.location + "'");
  }
  std::string description = "folder " + parsed.location + " (" + std::to_string(entries.size()) +
                            " images, " + stamps + ")";
  return std::unique_ptr<FrameSource>(
      std::make_unique<FolderFrameSource>(std::move(description), std::move(entries)));
}

}  // namespace groundline::io
