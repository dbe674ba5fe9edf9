// A dataset's sensor streams merged into one time-ordered sequence of
// events, as the sensors would have delivered them: wheel encoder readings,
// camera frames (the image file, not yet decoded) and LiDAR scans (read from
// lidar_scans.txt as they are reached, never all at once).
//
// Order: by stamp; events within 1 ns of each other (stamps that went through
// text) come scan, frame, wheel reading, so that a frame taken at a
// reading's instant is there when that reading is processed.
//
// Not thread-safe; movable.
#ifndef GROUNDLINE_CORE_DATASET_STREAMS_H_
#define GROUNDLINE_CORE_DATASET_STREAMS_H_

#include <filesystem>
#include <memory>
#include <optional>

#include "groundline/core/dataset.h"
#include "groundline/core/dataset_records.h"
#include "groundline/core/status.h"

namespace groundline::core {

struct DatasetEvent {
  enum class Kind { kScan, kFrame, kWheel };
  Kind kind = Kind::kWheel;
  double stamp_s = 0.0;
  WheelEncoderReading wheel;         // kWheel
  std::filesystem::path image_path;  // kFrame: the image file
  LaserScan scan;                    // kScan
};

struct DatasetStreamOptions {
  bool wheels = true;
  bool frames = true;
  bool scans = true;
};

class DatasetStreams {
 public:
  // dataset: read from dir with its wheel encoders and image index (the
  // scans are streamed from dir's lidar_scans file, not taken from it).
  // Errors: an unreadable scan file.
  static Result<DatasetStreams> Open(const std::filesystem::path& dir, const Dataset& dataset,
                                     const DatasetStreamOptions& options = {});
  DatasetStreams(DatasetStreams&&) noexcept;
  DatasetStreams& operator=(DatasetStreams&&) noexcept;
  ~DatasetStreams();

  // The next event; false at the end of every stream. Errors: a malformed
  // scan line (file and line named).
  Result<bool> Next(DatasetEvent* event);

 private:
  struct Impl;
  explicit DatasetStreams(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_DATASET_STREAMS_H_
