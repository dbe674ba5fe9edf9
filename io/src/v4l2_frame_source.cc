#include "v4l2_frame_source.h"

#include <fcntl.h>
#include <libv4l2.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/mman.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

#include "groundline/io/pixel_conversion.h"

namespace groundline::io {
namespace {

std::string FourCc(std::uint32_t code) {
  std::string s(4, ' ');
  for (int i = 0; i < 4; ++i) s[i] = static_cast<char>((code >> (8 * i)) & 0xff);
  return s;
}

// ioctl through libv4l2, retried on EINTR.
int Xioctl(int fd, unsigned long request, void* arg) {
  int r;
  do {
    r = v4l2_ioctl(fd, request, arg);
  } while (r == -1 && errno == EINTR);
  return r;
}

struct MappedBuffer {
  void* start = MAP_FAILED;
  std::size_t length = 0;
};

class V4l2FrameSource final : public FrameSource {
 public:
  explicit V4l2FrameSource(std::string device) : device_(std::move(device)) {}
  ~V4l2FrameSource() override {
    if (fd_ < 0) return;
    if (streaming_) {
      v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      Xioctl(fd_, VIDIOC_STREAMOFF, &type);
    }
    for (MappedBuffer& b : buffers_) {
      if (b.start != MAP_FAILED) v4l2_munmap(b.start, b.length);
    }
    v4l2_close(fd_);
  }
  V4l2FrameSource(const V4l2FrameSource&) = delete;
  V4l2FrameSource& operator=(const V4l2FrameSource&) = delete;

  core::Status Open(const FrameSourceOptions& options);
  core::Result<std::optional<Frame>> Next(double timeout_s) override;
  std::string Describe() const override { return description_; }
  bool IsLive() const override { return true; }
  const FrameSourceStats& stats() const override { return stats_; }

 private:
  core::Status Fail(const std::string& what) const {
    return core::Status::Error(device_ + ": " + what + ": " + std::strerror(errno));
  }
  core::Status SetFormat(const FrameSourceOptions& options);

  std::string device_;
  std::string description_;
  int fd_ = -1;
  bool streaming_ = false;
  bool latest_only_ = false;
  std::vector<MappedBuffer> buffers_;
  PixelFormat format_ = PixelFormat::kGrey;
  int width_px_ = 0, height_px_ = 0, stride_bytes_ = 0;
  FrameSourceStats stats_;
};

core::Status V4l2FrameSource::SetFormat(const FrameSourceOptions& options) {
  std::vector<std::uint32_t> offered;
  v4l2_fmtdesc desc{};
  desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (desc.index = 0; Xioctl(fd_, VIDIOC_ENUM_FMT, &desc) == 0; ++desc.index) {
    offered.push_back(desc.pixelformat);
  }
  const auto has = [&](std::uint32_t f) {
    return std::find(offered.begin(), offered.end(), f) != offered.end();
  };
  std::uint32_t chosen = 0;
  if (!options.pixel_format.empty()) {
    chosen = options.pixel_format == "GREY"   ? V4L2_PIX_FMT_GREY
             : options.pixel_format == "YUYV" ? V4L2_PIX_FMT_YUYV
                                              : V4L2_PIX_FMT_MJPEG;
    if (!has(chosen)) {
      std::string list;
      for (std::uint32_t f : offered) list += " " + FourCc(f);
      return core::Status::Error(device_ + ": format " + options.pixel_format +
                                 " not offered (the device offers:" + list + ")");
    }
  } else {
    for (std::uint32_t f :
         {V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_YUV420}) {
      if (has(f)) {
        chosen = f;
        break;
      }
    }
    if (chosen == 0) {
      return core::Status::Error(device_ + ": offers none of GREY, YUYV, MJPG, YU12");
    }
  }
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (Xioctl(fd_, VIDIOC_G_FMT, &fmt) != 0) return Fail("VIDIOC_G_FMT");
  if (options.width_px > 0) {
    fmt.fmt.pix.width = options.width_px;
    fmt.fmt.pix.height = options.height_px;
  }
  fmt.fmt.pix.pixelformat = chosen;
  fmt.fmt.pix.field = V4L2_FIELD_ANY;
  if (Xioctl(fd_, VIDIOC_S_FMT, &fmt) != 0) return Fail("VIDIOC_S_FMT " + FourCc(chosen));
  if (fmt.fmt.pix.pixelformat != chosen) {
    return core::Status::Error(device_ + ": asked for " + FourCc(chosen) + ", the driver set " +
                               FourCc(fmt.fmt.pix.pixelformat));
  }
  width_px_ = static_cast<int>(fmt.fmt.pix.width);
  height_px_ = static_cast<int>(fmt.fmt.pix.height);
  stride_bytes_ = static_cast<int>(fmt.fmt.pix.bytesperline);
  format_ = chosen == V4L2_PIX_FMT_GREY    ? PixelFormat::kGrey
            : chosen == V4L2_PIX_FMT_YUYV  ? PixelFormat::kYuyv
            : chosen == V4L2_PIX_FMT_MJPEG ? PixelFormat::kMjpeg
                                           : PixelFormat::kLumaPlane;
  if (stride_bytes_ == 0 && format_ != PixelFormat::kMjpeg) {
    stride_bytes_ = width_px_ * (format_ == PixelFormat::kYuyv ? 2 : 1);
  }
  if (options.width_px > 0 && (width_px_ != options.width_px || height_px_ != options.height_px)) {
    return core::Status::Error(device_ + ": asked for " + std::to_string(options.width_px) + "x" +
                               std::to_string(options.height_px) + ", the driver set " +
                               std::to_string(width_px_) + "x" + std::to_string(height_px_));
  }
  if (options.fps > 0.0) {
    v4l2_streamparm parm{};
    parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(options.fps * 1000.0);
    if (Xioctl(fd_, VIDIOC_S_PARM, &parm) != 0) return Fail("VIDIOC_S_PARM (fps)");
  }
  return core::Status::Ok();
}

core::Status V4l2FrameSource::Open(const FrameSourceOptions& options) {
  latest_only_ = options.latest_only;
  fd_ = v4l2_open(device_.c_str(), O_RDWR | O_NONBLOCK);
  if (fd_ < 0) return Fail("cannot open (is it a V4L2 device, and may this user open it?)");
  v4l2_capability cap{};
  if (Xioctl(fd_, VIDIOC_QUERYCAP, &cap) != 0) return Fail("VIDIOC_QUERYCAP (not a V4L2 device?)");
  const std::uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 || (caps & V4L2_CAP_STREAMING) == 0) {
    return core::Status::Error(device_ + " (" + reinterpret_cast<const char*>(cap.driver) +
                               "): not a streaming video capture device");
  }
  if (core::Status s = SetFormat(options); !s.ok()) return s;
  v4l2_requestbuffers req{};
  req.count = static_cast<std::uint32_t>(options.buffer_count);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (Xioctl(fd_, VIDIOC_REQBUFS, &req) != 0 || req.count < 2) return Fail("VIDIOC_REQBUFS");
  buffers_.resize(req.count);
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (Xioctl(fd_, VIDIOC_QUERYBUF, &buf) != 0) return Fail("VIDIOC_QUERYBUF");
    buffers_[i].length = buf.length;
    buffers_[i].start =
        v4l2_mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buf.m.offset);
    if (buffers_[i].start == MAP_FAILED) return Fail("mmap of buffer " + std::to_string(i));
    if (Xioctl(fd_, VIDIOC_QBUF, &buf) != 0) return Fail("VIDIOC_QBUF");
  }
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (Xioctl(fd_, VIDIOC_STREAMON, &type) != 0) return Fail("VIDIOC_STREAMON");
  streaming_ = true;
  description_ = "v4l2 " + device_ + " (" + reinterpret_cast<const char*>(cap.card) + ", " +
                 std::to_string(width_px_) + "x" + std::to_string(height_px_) + " " +
                 PixelFormatName(format_) + ", " + std::to_string(req.count) + " buffers)";
  return core::Status::Ok();
}

core::Result<std::optional<Frame>> V4l2FrameSource::Next(double timeout_s) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline =
      Clock::now() + std::chrono::microseconds(static_cast<std::int64_t>(timeout_s * 1e6));
  for (;;) {
    const auto left_ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left_ms <= 0) {
      return core::Status::Error(device_ + ": no frame within " + std::to_string(timeout_s) +
                                 " s (is the camera streaming? is the trigger connected?)");
    }
    pollfd pfd{fd_, POLLIN, 0};
    const int ready = poll(&pfd, 1, static_cast<int>(left_ms));
    if (ready < 0 && errno != EINTR) return Fail("poll");
    if (ready <= 0) continue;
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    if (Xioctl(fd_, VIDIOC_DQBUF, &buf) != 0) {
      if (errno == EAGAIN) continue;
      return Fail("VIDIOC_DQBUF");
    }
    if (latest_only_) {
      v4l2_buffer newer{};
      newer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      newer.memory = V4L2_MEMORY_MMAP;
      while (Xioctl(fd_, VIDIOC_DQBUF, &newer) == 0) {
        if (Xioctl(fd_, VIDIOC_QBUF, &buf) != 0) return Fail("VIDIOC_QBUF");
        ++stats_.dropped;
        buf = newer;
      }
    }
    const MappedBuffer& mapped = buffers_[buf.index];
    core::Result<cv::Mat> grey =
        (buf.flags & V4L2_BUF_FLAG_ERROR) != 0
            ? core::Result<cv::Mat>(core::Status::Error("the driver flagged the buffer corrupt"))
            : ConvertToGrey(format_, static_cast<const std::uint8_t*>(mapped.start),
                            std::min<std::size_t>(buf.bytesused, mapped.length), width_px_,
                            height_px_, stride_bytes_);
    if (Xioctl(fd_, VIDIOC_QBUF, &buf) != 0) return Fail("VIDIOC_QBUF");
    if (!grey.ok()) {
      ++stats_.skipped;
      stats_.skipped_reasons.push_back(device_ + " frame " + std::to_string(buf.sequence) + ": " +
                                       grey.message() + "; skipped");
      continue;
    }
    Frame frame;
    frame.grey = std::move(grey).value();
    frame.stamp_s = static_cast<double>(buf.timestamp.tv_sec) + 1e-6 * buf.timestamp.tv_usec;
    frame.sequence = buf.sequence;
    char name[40];
    std::snprintf(name, sizeof(name), "frame_%06u.png", buf.sequence);
    frame.name = name;
    ++stats_.delivered;
    return std::optional<Frame>(std::move(frame));
  }
}

}  // namespace

core::Result<std::unique_ptr<FrameSource>> OpenV4l2FrameSource(const std::string& uri,
                                                               const FrameSourceUri& parsed) {
  auto source = std::make_unique<V4l2FrameSource>(parsed.location);
  if (core::Status s = source->Open(parsed.options); !s.ok()) return s.WithContext(uri);
  return std::unique_ptr<FrameSource>(std::move(source));
}

}  // namespace groundline::io
