// Camera frames from a folder of images, a V4L2 device or a libcamera camera,
// behind one interface, so that a flow written against FrameSource (the live
// calibration, later the live localization) runs unchanged on recorded images
// in CI and on the vehicle's camera.
//
// URIs (OpenFrameSource):
//   folder:DIR | DIR | GLOB   images of a directory (.png .jpg .jpeg .bmp .pgm
//                             .tif .tiff), or of a glob on file names
//                             ("views/cam0_*.png"), sorted by name. When DIR
//                             (or DIR/images) holds a dataset image index
//                             (index.csv, docs/dataset.md) its files and stamps
//                             are used; otherwise frame i is stamped i / rate.
//                             Query: ?rate=HZ.
//   v4l2:/dev/videoN          a V4L2 capture device through libv4l2 (mmap
//                             streaming). Query: width, height (px), fps,
//                             format=GREY|YUYV|MJPG, buffers.
//   libcamera:N | libcamera:ID  the N-th camera libcamera lists (0-based) or
//                             the camera of that id. Query: width, height, fps,
//                             buffers.
// Query values are "key=value" pairs after '?', joined by '&'
// ("v4l2:/dev/video0?width=1280&height=800&format=YUYV&fps=30"; for a folder
// glob, whose '?' is a wildcard, only a last '?' followed by key=value); they override
// FrameSourceOptions. Unknown schemes, keys or malformed values are errors that
// name the URI and what was expected.
//
// Frames are 8-bit grey. Every consumer in groundline (board and tag
// detection, the bird's-eye remap, line extraction) works on intensity, so
// colour is dropped at the source (YUV: the Y plane; MJPEG and colour files:
// decoded to grey by OpenCV), once, instead of in every consumer.
//
// Thread-safety: a FrameSource is used from one thread.
#ifndef GROUNDLINE_IO_FRAME_SOURCE_H_
#define GROUNDLINE_IO_FRAME_SOURCE_H_

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::io {

struct Frame {
  cv::Mat grey;  // CV_8UC1, owns its pixels (never aliases a driver buffer)
  // Folder: the index stamp or sequence / rate. Cameras: the driver's buffer
  // timestamp (V4L2: the buffer's timeval, normally CLOCK_MONOTONIC;
  // libcamera: FrameMetadata::timestamp, start of exposure), seconds.
  double stamp_s = 0.0;
  // Folder: 0, 1, 2, ... over the frames delivered. Cameras: the driver's
  // frame counter, so a gap means frames were dropped.
  std::uint64_t sequence = 0;
  // Folder: the file name (no directory). Cameras: "frame_NNNNNN.png" from
  // the sequence, the name a saved copy of the frame gets.
  std::string name;
};

struct FrameSourceOptions {
  double folder_rate_hz = 10.0;  // stamps of a folder without an image index
  int width_px = 0;              // cameras: requested size; 0 = the driver's default
  int height_px = 0;
  double fps = 0.0;          // cameras: requested frame rate; 0 = the driver's default
  std::string pixel_format;  // V4L2: "GREY", "YUYV" or "MJPG"; "" = first supported
  int buffer_count = 4;      // cameras: driver buffers in flight
  // Cameras: deliver the newest frame waiting, returning older ones to the
  // driver unread (counted in FrameSourceStats::dropped). Interactive flows
  // (live calibration guidance) want the current view, not one from several
  // frames ago when their processing is slower than the camera; recording
  // flows want every frame (false).
  bool latest_only = false;
  core::Status Validate() const;
};

struct FrameSourceStats {
  std::uint64_t delivered = 0;
  // Frames skipped: unreadable or corrupt files, buffers the driver flagged
  // as corrupt, MJPEG frames that do not decode. One reason per skipped frame
  // (the file name or sequence and what was wrong).
  std::uint64_t skipped = 0;
  std::vector<std::string> skipped_reasons;
  std::uint64_t dropped = 0;  // older frames passed over by latest_only
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The next frame. std::nullopt when the stream ended (a folder's last image
  // was delivered; a camera never ends). An error when the device failed or
  // no frame arrived within timeout_s; corrupt frames are skipped (stats())
  // and never returned as errors.
  virtual core::Result<std::optional<Frame>> Next(double timeout_s) = 0;
  // "folder /data/views (13 images)", "v4l2 /dev/video0 (uvcvideo, 1280x800 YUYV)".
  virtual std::string Describe() const = 0;
  // True for a camera (frames arrive in real time and never end).
  virtual bool IsLive() const = 0;
  virtual const FrameSourceStats& stats() const = 0;
};

enum class FrameSourceKind { kFolder, kV4l2, kLibcamera };

struct FrameSourceUri {
  FrameSourceKind kind = FrameSourceKind::kFolder;
  std::string location;        // folder/glob, device path, or libcamera index or id
  FrameSourceOptions options;  // the defaults given, overridden by the query
};

// Parses a URI (file comment) without touching the file system or devices.
core::Result<FrameSourceUri> ParseFrameSourceUri(const std::string& uri,
                                                 const FrameSourceOptions& defaults = {});

// Opens (and for cameras, starts streaming from) the source of a URI.
core::Result<std::unique_ptr<FrameSource>> OpenFrameSource(const std::string& uri,
                                                           const FrameSourceOptions& defaults = {});

// The image files of a directory, or of a glob on file names, sorted by name
// (extensions of the file comment, case-insensitive). Empty when none match.
std::vector<std::string> ListImageFiles(const std::string& directory_or_glob);

// The ids of the cameras libcamera finds on this machine (starts and stops a
// CameraManager, so not while a libcamera source is open: libcamera allows
// one manager per process). An error when the manager does not start.
core::Result<std::vector<std::string>> ListLibcameraCameras();

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_FRAME_SOURCE_H_
