// The frame source of a libcamera camera (libcamera 0.0.3, Debian 12); see
// frame_source.h.
//
// CameraManager started, the camera chosen by index (in the order
// CameraManager::cameras() lists them) or id, acquired, configured for one
// Viewfinder stream with the first of R8, YUYV, YUV420, NV12, NV21, MJPEG the
// stream offers (and the requested size), FrameBufferAllocator buffers, one
// Request per buffer. requestCompleted (libcamera's thread) pushes completed
// requests into a queue; Next() (the caller's thread) waits on it with the
// timeout, reads plane 0 of the buffer through an mmap of its dmabuf (mapped
// once per buffer), converts it (pixel_conversion.h), then reuses and queues
// the request again. The frame rate goes in as FrameDurationLimits at start.
// The destructor stops the camera, frees the buffers, releases the camera and
// stops the manager, in that order.
#ifndef GROUNDLINE_IO_LIBCAMERA_FRAME_SOURCE_H_
#define GROUNDLINE_IO_LIBCAMERA_FRAME_SOURCE_H_

#include <memory>
#include <string>
#include <vector>

#include "groundline/io/frame_source.h"

namespace groundline::io {

// Fails, naming the URI, when no camera matches (listing those found), or
// the camera refuses the configuration or the buffers.
core::Result<std::unique_ptr<FrameSource>> OpenLibcameraFrameSource(const std::string& uri,
                                                                    const FrameSourceUri& parsed);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_LIBCAMERA_FRAME_SOURCE_H_
