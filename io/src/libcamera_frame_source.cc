#include "libcamera_frame_source.h"

#include <sys/mman.h>

#include <libcamera/libcamera.h>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>

#include "groundline/core/text_parse.h"
#include "groundline/io/pixel_conversion.h"

namespace groundline::io {
namespace {

namespace lc = libcamera;

struct Mapping {
  void* start = MAP_FAILED;
  std::size_t length = 0;
};

class LibcameraFrameSource final : public FrameSource {
 public:
  explicit LibcameraFrameSource(std::string uri) : uri_(std::move(uri)) {}
  ~LibcameraFrameSource() override {
    if (started_) camera_->stop();
    if (camera_) camera_->requestCompleted.disconnect(this);
    requests_.clear();
    for (auto& [buffer, m] : mappings_) munmap(m.start, m.length);
    if (allocator_ && stream_ != nullptr) allocator_->free(stream_);
    allocator_.reset();
    if (acquired_) camera_->release();
    camera_.reset();
    if (manager_) manager_->stop();
  }
  LibcameraFrameSource(const LibcameraFrameSource&) = delete;
  LibcameraFrameSource& operator=(const LibcameraFrameSource&) = delete;

  core::Status Open(const std::string& location, const FrameSourceOptions& options);
  core::Result<std::optional<Frame>> Next(double timeout_s) override;
  std::string Describe() const override { return description_; }
  bool IsLive() const override { return true; }
  const FrameSourceStats& stats() const override { return stats_; }

 private:
  void OnRequestCompleted(lc::Request* request) {
    std::lock_guard<std::mutex> lock(mutex_);
    completed_.push_back(request);
    ready_.notify_one();
  }
  core::Status Configure(const FrameSourceOptions& options);
  core::Status Error(const std::string& what) const {
    return core::Status::Error(uri_ + ": " + what);
  }

  std::string uri_;
  std::string description_;
  std::unique_ptr<lc::CameraManager> manager_;
  std::shared_ptr<lc::Camera> camera_;
  std::unique_ptr<lc::CameraConfiguration> config_;
  std::unique_ptr<lc::FrameBufferAllocator> allocator_;
  lc::Stream* stream_ = nullptr;
  std::vector<std::unique_ptr<lc::Request>> requests_;
  std::map<const lc::FrameBuffer*, Mapping> mappings_;
  bool acquired_ = false, started_ = false;
  bool latest_only_ = false;
  PixelFormat format_ = PixelFormat::kGrey;
  int width_px_ = 0, height_px_ = 0, stride_bytes_ = 0;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<lc::Request*> completed_;
  FrameSourceStats stats_;
};

core::Status LibcameraFrameSource::Configure(const FrameSourceOptions& options) {
  config_ = camera_->generateConfiguration({lc::StreamRole::Viewfinder});
  if (!config_ || config_->size() != 1) return Error("no viewfinder configuration");
  lc::StreamConfiguration& sc = config_->at(0);
  const std::vector<lc::PixelFormat> offered = sc.formats().pixelformats();
  const std::pair<lc::PixelFormat, PixelFormat> preference[] = {
      {lc::formats::R8, PixelFormat::kGrey},          {lc::formats::YUYV, PixelFormat::kYuyv},
      {lc::formats::YUV420, PixelFormat::kLumaPlane}, {lc::formats::NV12, PixelFormat::kLumaPlane},
      {lc::formats::NV21, PixelFormat::kLumaPlane},   {lc::formats::MJPEG, PixelFormat::kMjpeg}};
  bool found = false;
  for (const auto& [lc_format, format] : preference) {
    if (std::find(offered.begin(), offered.end(), lc_format) != offered.end()) {
      sc.pixelFormat = lc_format;
      format_ = format;
      found = true;
      break;
    }
  }
  if (!found) {
    std::string list;
    for (const lc::PixelFormat& f : offered) list += " " + f.toString();
    return Error("the stream offers none of R8, YUYV, YUV420, NV12, NV21, MJPEG (offers:" + list +
                 ")");
  }
  if (options.width_px > 0) sc.size = lc::Size(options.width_px, options.height_px);
  sc.bufferCount = static_cast<unsigned int>(options.buffer_count);
  if (config_->validate() == lc::CameraConfiguration::Invalid) {
    return Error("configuration " + sc.toString() + " is invalid for this camera");
  }
  if (options.width_px > 0 && (static_cast<int>(sc.size.width) != options.width_px ||
                               static_cast<int>(sc.size.height) != options.height_px)) {
    return Error("asked for " + std::to_string(options.width_px) + "x" +
                 std::to_string(options.height_px) + ", the camera offers " + sc.size.toString());
  }
  if (camera_->configure(config_.get()) != 0)
    return Error("configure(" + sc.toString() + ") failed");
  stream_ = sc.stream();
  width_px_ = static_cast<int>(sc.size.width);
  height_px_ = static_cast<int>(sc.size.height);
  stride_bytes_ = static_cast<int>(sc.stride);
  return core::Status::Ok();
}

core::Status LibcameraFrameSource::Open(const std::string& location,
                                        const FrameSourceOptions& options) {
  latest_only_ = options.latest_only;
  manager_ = std::make_unique<lc::CameraManager>();
  if (manager_->start() != 0) {
    manager_.reset();
    return Error("the libcamera camera manager does not start");
  }
  const std::vector<std::shared_ptr<lc::Camera>> cameras = manager_->cameras();
  const std::optional<std::int64_t> index = core::ParseInt(location);
  if (index && *index >= 0 && *index < static_cast<std::int64_t>(cameras.size())) {
    camera_ = cameras[static_cast<std::size_t>(*index)];
  } else if (!index) {
    camera_ = manager_->get(location);
  }
  if (!camera_) {
    std::string list;
    for (const auto& c : cameras) list += " '" + c->id() + "'";
    return Error("no camera " + location + " (" + std::to_string(cameras.size()) +
                 " camera(s) found" + (list.empty() ? "" : ":" + list) + ")");
  }
  if (camera_->acquire() != 0) return Error(camera_->id() + " is in use by another process");
  acquired_ = true;
  if (core::Status s = Configure(options); !s.ok()) return s;
  allocator_ = std::make_unique<lc::FrameBufferAllocator>(camera_);
  if (allocator_->allocate(stream_) < 0) return Error("cannot allocate frame buffers");
  for (const std::unique_ptr<lc::FrameBuffer>& buffer : allocator_->buffers(stream_)) {
    const lc::FrameBuffer::Plane& plane = buffer->planes().front();
    Mapping m;
    m.length = plane.offset + plane.length;
    m.start = mmap(nullptr, m.length, PROT_READ, MAP_SHARED, plane.fd.get(), 0);
    if (m.start == MAP_FAILED) return Error("cannot mmap a frame buffer");
    mappings_[buffer.get()] = m;
    std::unique_ptr<lc::Request> request = camera_->createRequest();
    if (!request || request->addBuffer(stream_, buffer.get()) != 0) {
      return Error("cannot create a request");
    }
    requests_.push_back(std::move(request));
  }
  camera_->requestCompleted.connect(this, &LibcameraFrameSource::OnRequestCompleted);
  lc::ControlList controls;
  if (options.fps > 0.0) {
    const std::int64_t frame_us = static_cast<std::int64_t>(1e6 / options.fps);
    controls.set(lc::controls::FrameDurationLimits,
                 lc::Span<const std::int64_t, 2>({frame_us, frame_us}));
  }
  if (camera_->start(&controls) != 0) return Error("camera start failed");
  started_ = true;
  for (std::unique_ptr<lc::Request>& request : requests_) {
    if (camera_->queueRequest(request.get()) != 0) return Error("cannot queue a request");
  }
  description_ = "libcamera " + camera_->id() + " (" + config_->at(0).toString() + ", " +
                 std::to_string(requests_.size()) + " buffers)";
  return core::Status::Ok();
}

core::Result<std::optional<Frame>> LibcameraFrameSource::Next(double timeout_s) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline =
      Clock::now() + std::chrono::microseconds(static_cast<std::int64_t>(timeout_s * 1e6));
  for (;;) {
    lc::Request* request = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (!ready_.wait_until(lock, deadline, [this] { return !completed_.empty(); })) {
        return Error("no frame within " + std::to_string(timeout_s) + " s");
      }
      request = completed_.front();
      completed_.pop_front();
      while (latest_only_ && !completed_.empty() &&
             request->status() != lc::Request::RequestCancelled) {
        request->reuse(lc::Request::ReuseBuffers);
        if (camera_->queueRequest(request) != 0) return Error("cannot queue a request again");
        ++stats_.dropped;
        request = completed_.front();
        completed_.pop_front();
      }
    }
    if (request->status() == lc::Request::RequestCancelled) {
      return Error("the camera cancelled a request (was it stopped or unplugged?)");
    }
    const lc::FrameBuffer* buffer = request->buffers().at(stream_);
    const lc::FrameMetadata& meta = buffer->metadata();
    const lc::FrameBuffer::Plane& plane = buffer->planes().front();
    const Mapping& m = mappings_.at(buffer);
    const std::size_t used =
        meta.planes().empty() ? plane.length : std::min(meta.planes()[0].bytesused, plane.length);
    core::Result<cv::Mat> grey =
        meta.status != lc::FrameMetadata::FrameSuccess
            ? core::Result<cv::Mat>(core::Status::Error("the camera flagged the frame an error"))
            : ConvertToGrey(format_, static_cast<const std::uint8_t*>(m.start) + plane.offset, used,
                            width_px_, height_px_, stride_bytes_);
    const std::uint64_t sequence = meta.sequence;
    const double stamp_s = 1e-9 * static_cast<double>(meta.timestamp);
    request->reuse(lc::Request::ReuseBuffers);
    if (camera_->queueRequest(request) != 0) return Error("cannot queue a request again");
    if (!grey.ok()) {
      ++stats_.skipped;
      stats_.skipped_reasons.push_back(uri_ + " frame " + std::to_string(sequence) + ": " +
                                       grey.message() + "; skipped");
      continue;
    }
    Frame frame;
    frame.grey = std::move(grey).value();
    frame.stamp_s = stamp_s;
    frame.sequence = sequence;
    char name[40];
    std::snprintf(name, sizeof(name), "frame_%06llu.png",
                  static_cast<unsigned long long>(sequence));
    frame.name = name;
    ++stats_.delivered;
    return std::optional<Frame>(std::move(frame));
  }
}

}  // namespace

core::Result<std::unique_ptr<FrameSource>> OpenLibcameraFrameSource(const std::string& uri,
                                                                    const FrameSourceUri& parsed) {
  auto source = std::make_unique<LibcameraFrameSource>(uri);
  if (core::Status s = source->Open(parsed.location, parsed.options); !s.ok()) return s;
  return std::unique_ptr<FrameSource>(std::move(source));
}

core::Result<std::vector<std::string>> ListLibcameraCameras() {
  lc::CameraManager manager;
  if (manager.start() != 0) {
    return core::Status::Error("the libcamera camera manager does not start");
  }
  std::vector<std::string> ids;
  for (const std::shared_ptr<lc::Camera>& c : manager.cameras()) ids.push_back(c->id());
  manager.stop();
  return ids;
}

}  // namespace groundline::io
