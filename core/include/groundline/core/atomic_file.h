// Writing files so that a reader never sees a half-written one: the content
// goes to "<path>.tmp.<pid>" in the same directory, is flushed, and is then
// renamed over <path> (atomic on POSIX file systems).
#ifndef GROUNDLINE_CORE_ATOMIC_FILE_H_
#define GROUNDLINE_CORE_ATOMIC_FILE_H_

#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

#include "groundline/core/status.h"

namespace groundline::core {

// Calls `write` with a stream on the temporary file; renames it to `path` if
// `write` returns ok and the stream is good, else removes it and returns the error.
// Creates missing parent directories.
Status WriteFileAtomically(const std::filesystem::path& path,
                           const std::function<Status(std::ostream&)>& write);

Status WriteFileAtomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_ATOMIC_FILE_H_
