// The frame source of a folder (or glob) of images; see frame_source.h.
#ifndef GROUNDLINE_IO_FOLDER_FRAME_SOURCE_H_
#define GROUNDLINE_IO_FOLDER_FRAME_SOURCE_H_

#include <memory>
#include <string>

#include "groundline/io/frame_source.h"

namespace groundline::io {

// Fails when the folder cannot be listed, holds no image file, or its image
// index (index.csv) is malformed or lists a missing file.
core::Result<std::unique_ptr<FrameSource>> OpenFolderFrameSource(const std::string& uri,
                                                                 const FrameSourceUri& parsed);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_FOLDER_FRAME_SOURCE_H_
