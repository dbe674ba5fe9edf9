// Line-by-line reading of text files that may be compressed.
//
// LineReader opens a plain, gzip or bzip2 file. The compression is detected
// from the first bytes of the file (gzip: 1f 8b; bzip2: "BZh" followed by a
// block-size digit '1'..'9'), never from the file name, so `log.clf` holding
// bzip2 data and `log.clf.gz` holding plain text both read correctly.
// Concatenated gzip members and concatenated bzip2 streams (as written by
// pigz / pbzip2 or `cat a.bz2 b.bz2`) are read as one text.
//
// Lines are split at '\n'; the '\n' and one trailing '\r' (CRLF files) are
// removed. A last line without a final '\n' is still returned. The reader
// counts the lines it has returned, so parsers can name "file:line" in their
// messages.
//
// Errors (the file cannot be opened, the compressed data is corrupt or
// truncated, a read fails) name the file and, when reading, the line number
// reached. A LineReader owns its C library handles (FILE*, gzFile, BZFILE*)
// and releases them in its destructor. It is movable, not copyable, and not
// thread-safe: use one reader per thread.
#ifndef GROUNDLINE_IO_COMPRESSED_FILE_H_
#define GROUNDLINE_IO_COMPRESSED_FILE_H_

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "groundline/core/status.h"

namespace groundline::io {

enum class Compression { kNone, kGzip, kBzip2 };

namespace detail {
// One decompression backend (plain, zlib, libbz2); defined in the source file.
class ByteSource;
}  // namespace detail

// "plain", "gzip" or "bzip2".
std::string_view CompressionName(Compression compression);

// Detects the compression of a file from its magic bytes. A file shorter than
// a magic number (including an empty file) is plain.
core::Result<Compression> DetectCompression(const std::filesystem::path& path);

class LineReader {
 public:
  // Opens `path`, detecting its compression.
  static core::Result<LineReader> Open(const std::filesystem::path& path);

  LineReader(LineReader&&) noexcept;
  LineReader& operator=(LineReader&&) noexcept;
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;
  ~LineReader();

  // Reads the next line into *line (replacing its content). Returns false at
  // the end of the file or on an error; after false, status() tells which.
  // Typical use:
  //   std::string line;
  //   while (reader.ReadLine(&line)) { ... reader.line_number() ... }
  //   if (!reader.status().ok()) return reader.status();
  bool ReadLine(std::string* line);

  // Ok unless a read or decompression error occurred. The message names the
  // file and the line number reached.
  const core::Status& status() const { return status_; }

  // 1-based number of the line last returned by ReadLine; 0 before the first.
  int64_t line_number() const { return line_number_; }
  const std::filesystem::path& path() const { return path_; }
  Compression compression() const { return compression_; }

 private:
  LineReader(std::filesystem::path path, Compression compression,
             std::unique_ptr<detail::ByteSource> source);
  // Refills buffer_ from the source. Returns false at the end of data or on
  // an error (then status_ is set).
  bool Refill();

  std::filesystem::path path_;
  Compression compression_ = Compression::kNone;
  std::unique_ptr<detail::ByteSource> source_;
  std::string buffer_;          // decompressed bytes not yet returned
  std::size_t buffer_pos_ = 0;  // first unread byte in buffer_
  bool source_done_ = false;
  int64_t line_number_ = 0;
  core::Status status_ = core::Status::Ok();
};

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_COMPRESSED_FILE_H_
