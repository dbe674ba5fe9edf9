#include "groundline/core/dataset_streams.h"

#include <limits>

namespace groundline::core {
namespace {

// Events closer than this are simultaneous (stamps that went through text).
constexpr double kSimultaneousS = 1e-9;

}  // namespace

struct DatasetStreams::Impl {
  const std::vector<WheelEncoderReading>* wheels = nullptr;
  const std::vector<ImageRecord>* images = nullptr;
  std::filesystem::path image_dir;
  std::optional<LaserScanReader> scans;
  std::optional<LaserScan> next_scan;
  std::size_t next_wheel = 0;
  std::size_t next_image = 0;
};

DatasetStreams::DatasetStreams(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
DatasetStreams::DatasetStreams(DatasetStreams&&) noexcept = default;
DatasetStreams& DatasetStreams::operator=(DatasetStreams&&) noexcept = default;
DatasetStreams::~DatasetStreams() = default;

Result<DatasetStreams> DatasetStreams::Open(const std::filesystem::path& dir,
                                            const Dataset& dataset,
                                            const DatasetStreamOptions& options) {
  auto impl = std::make_unique<Impl>();
  static const std::vector<WheelEncoderReading> kNoWheels;
  static const std::vector<ImageRecord> kNoImages;
  impl->wheels = options.wheels ? &dataset.wheel_encoders : &kNoWheels;
  impl->images = options.frames ? &dataset.images : &kNoImages;
  impl->image_dir = (dir / dataset.manifest.files.image_index).parent_path();
  if (options.scans && !dataset.manifest.files.lidar_scans.empty()) {
    Result<LaserScanReader> reader =
        LaserScanReader::Open(dir / dataset.manifest.files.lidar_scans);
    if (!reader.ok()) return reader.status();
    impl->scans.emplace(std::move(reader).value());
  }
  return DatasetStreams(std::move(impl));
}

Result<bool> DatasetStreams::Next(DatasetEvent* event) {
  Impl& m = *impl_;
  if (m.scans && !m.next_scan) {
    LaserScan scan;
    Result<bool> read = m.scans->Next(&scan);
    if (!read.ok()) return read.status();
    if (*read) {
      m.next_scan = std::move(scan);
    } else {
      m.scans.reset();
    }
  }
  constexpr double kNone = std::numeric_limits<double>::infinity();
  const double scan_s = m.next_scan ? m.next_scan->stamp_s : kNone;
  const double frame_s =
      m.next_image < m.images->size() ? (*m.images)[m.next_image].stamp_s : kNone;
  const double wheel_s =
      m.next_wheel < m.wheels->size() ? (*m.wheels)[m.next_wheel].stamp_s : kNone;
  if (scan_s == kNone && frame_s == kNone && wheel_s == kNone) return false;
  if (scan_s <= frame_s + kSimultaneousS && scan_s <= wheel_s + kSimultaneousS) {
    event->kind = DatasetEvent::Kind::kScan;
    event->stamp_s = scan_s;
    event->scan = std::move(*m.next_scan);
    m.next_scan.reset();
  } else if (frame_s <= wheel_s + kSimultaneousS) {
    const ImageRecord& image = (*m.images)[m.next_image++];
    event->kind = DatasetEvent::Kind::kFrame;
    event->stamp_s = image.stamp_s;
    event->image_path = m.image_dir / image.file;
  } else {
    event->kind = DatasetEvent::Kind::kWheel;
    event->stamp_s = wheel_s;
    event->wheel = (*m.wheels)[m.next_wheel++];
  }
  return true;
}

}  // namespace groundline::core
