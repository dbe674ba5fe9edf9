// The frame source of a V4L2 capture device through libv4l2; see
// frame_source.h.
//
// Streaming I/O with mmap'ed driver buffers: VIDIOC_S_FMT with the requested
// size and format (else the first of GREY, YUYV, MJPG the device offers, else
// libv4l2's emulated YU12, whose Y plane is the grey image), VIDIOC_S_PARM for
// the frame rate, VIDIOC_REQBUFS + QUERYBUF + v4l2_mmap, all buffers queued,
// STREAMON. Next() polls the device with the timeout, dequeues a buffer,
// converts it (pixel_conversion.h) and queues it back at once. Buffers the
// driver flags V4L2_BUF_FLAG_ERROR, and MJPEG frames that do not decode, are
// skipped and counted. The destructor stops streaming and unmaps the buffers.
#ifndef GROUNDLINE_IO_V4L2_FRAME_SOURCE_H_
#define GROUNDLINE_IO_V4L2_FRAME_SOURCE_H_

#include <memory>
#include <string>

#include "groundline/io/frame_source.h"

namespace groundline::io {

// Fails, naming the device and the ioctl, when the device cannot be opened,
// is not a streaming capture device, or refuses the format or the buffers.
core::Result<std::unique_ptr<FrameSource>> OpenV4l2FrameSource(const std::string& uri,
                                                               const FrameSourceUri& parsed);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_V4L2_FRAME_SOURCE_H_
