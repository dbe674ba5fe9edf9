#include "groundline/io/compressed_file.h"

#include <bzlib.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <utility>

namespace groundline::io {
namespace detail {

// A stream of decompressed bytes.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  // Reads up to `capacity` bytes into `data`; returns how many, 0 at the end
  // of the data. An error message does not name the file (the caller does).
  virtual core::Result<std::size_t> Read(char* data, std::size_t capacity) = 0;
};

}  // namespace detail
namespace {

constexpr std::size_t kChunkBytes = 1 << 16;

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

struct GzCloser {
  void operator()(gzFile file) const { gzclose(file); }
};
using GzPtr = std::unique_ptr<gzFile_s, GzCloser>;

struct BzCloser {
  void operator()(BZFILE* file) const {
    int error = BZ_OK;
    BZ2_bzReadClose(&error, file);
  }
};
using BzPtr = std::unique_ptr<BZFILE, BzCloser>;

std::string ErrnoText() { return std::strerror(errno); }

core::Result<FilePtr> OpenFile(const std::filesystem::path& path) {
  errno = 0;
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (file == nullptr) {
    return core::Status::Error(path.string() + ": cannot open for reading: " + ErrnoText());
  }
  return file;
}

class PlainSource final : public detail::ByteSource {
 public:
  explicit PlainSource(FilePtr file) : file_(std::move(file)) {}
  core::Result<std::size_t> Read(char* data, std::size_t capacity) override {
    const std::size_t n = std::fread(data, 1, capacity, file_.get());
    if (n == 0 && std::ferror(file_.get())) {
      return core::Status::Error("read failed: " + ErrnoText());
    }
    return n;
  }

 private:
  FilePtr file_;
};

class GzipSource final : public detail::ByteSource {
 public:
  explicit GzipSource(GzPtr file) : file_(std::move(file)) {}
  core::Result<std::size_t> Read(char* data, std::size_t capacity) override {
    const unsigned request = static_cast<unsigned>(std::min<std::size_t>(capacity, INT_MAX));
    const int n = gzread(file_.get(), data, request);
    int error = Z_OK;
    const char* message = gzerror(file_.get(), &error);
    if (n < 0 || (n == 0 && error != Z_OK)) {
      // zlib reports a truncated stream as Z_BUF_ERROR "unexpected end of file".
      return core::Status::Error(std::string("gzip data is corrupt or truncated: ") +
                                 (message != nullptr ? message : "unknown zlib error"));
    }
    return static_cast<std::size_t>(n);
  }

 private:
  GzPtr file_;
};

// libbz2's BZ2_bzRead stops at the end of one stream; files made by pbzip2 or
// by concatenation hold several, so a new reader is opened on the bytes that
// follow. Non-bzip2 bytes after a complete stream are ignored, as the bzip2
// tool does ("trailing garbage after EOF ignored").
class Bzip2Source final : public detail::ByteSource {
 public:
  explicit Bzip2Source(FilePtr file) : file_(std::move(file)) {}

  core::Status Start(const char* unused, int unused_count) {
    int error = BZ_OK;
    bz_.reset(BZ2_bzReadOpen(&error, file_.get(), /*verbosity=*/0, /*small=*/0,
                             const_cast<char*>(unused), unused_count));
    if (error != BZ_OK) {
      bz_.reset();
      return core::Status::Error("cannot start bzip2 decompression (libbz2 error " +
                                 std::to_string(error) + ")");
    }
    return core::Status::Ok();
  }

  core::Result<std::size_t> Read(char* data, std::size_t capacity) override {
    while (bz_ != nullptr) {
      int error = BZ_OK;
      const int request = static_cast<int>(std::min<std::size_t>(capacity, INT_MAX));
      const int n = BZ2_bzRead(&error, bz_.get(), data, request);
      if (error == BZ_OK) return static_cast<std::size_t>(n);
      if (error == BZ_STREAM_END) {
        if (core::Status next = StartNextStream(); !next.ok()) return next;
        if (n > 0) return static_cast<std::size_t>(n);
        continue;
      }
      if (error == BZ_DATA_ERROR_MAGIC && streams_done_ > 0) {
        bz_.reset();  // trailing garbage after a complete stream
        return std::size_t{0};
      }
      return core::Status::Error(BzErrorText(error));
    }
    return std::size_t{0};
  }

 private:
  core::Status StartNextStream() {
    ++streams_done_;
    int error = BZ_OK;
    void* unused_ptr = nullptr;
    int unused_count = 0;
    BZ2_bzReadGetUnused(&error, bz_.get(), &unused_ptr, &unused_count);
    std::array<char, BZ_MAX_UNUSED> unused{};
    if (unused_count > 0) {
      std::memcpy(unused.data(), unused_ptr, static_cast<std::size_t>(unused_count));
    }
    bz_.reset();
    if (unused_count == 0) {
      const int c = std::fgetc(file_.get());
      if (c == EOF) return core::Status::Ok();  // bz_ stays null: end of data
      std::ungetc(c, file_.get());
    }
    return Start(unused.data(), unused_count);
  }

  static std::string BzErrorText(int error) {
    switch (error) {
      case BZ_UNEXPECTED_EOF:
        return "bzip2 data is truncated (unexpected end of file)";
      case BZ_DATA_ERROR:
        return "bzip2 data is corrupt (checksum or structure error)";
      case BZ_DATA_ERROR_MAGIC:
        return "bzip2 data is corrupt (bad stream header)";
      case BZ_IO_ERROR:
        return "read failed: " + ErrnoText();
      case BZ_MEM_ERROR:
        return "bzip2 decompression ran out of memory";
      default:
        return "bzip2 decompression failed (libbz2 error " + std::to_string(error) + ")";
    }
  }

  FilePtr file_;  // declared first: destroyed after bz_, which reads from it
  BzPtr bz_;
  int streams_done_ = 0;
};

}  // namespace

std::string_view CompressionName(Compression compression) {
  switch (compression) {
    case Compression::kNone:
      return "plain";
    case Compression::kGzip:
      return "gzip";
    case Compression::kBzip2:
      return "bzip2";
  }
  return "unknown";
}

core::Result<Compression> DetectCompression(const std::filesystem::path& path) {
  core::Result<FilePtr> file = OpenFile(path);
  if (!file.ok()) return file.status();
  std::array<unsigned char, 4> magic{};
  const std::size_t n = std::fread(magic.data(), 1, magic.size(), file->get());
  if (n == 0 && std::ferror(file->get())) {
    return core::Status::Error(path.string() + ": read failed: " + ErrnoText());
  }
  if (n >= 2 && magic[0] == 0x1f && magic[1] == 0x8b) return Compression::kGzip;
  if (n >= 4 && magic[0] == 'B' && magic[1] == 'Z' && magic[2] == 'h' && magic[3] >= '1' &&
      magic[3] <= '9') {
    return Compression::kBzip2;
  }
  return Compression::kNone;
}

core::Result<LineReader> LineReader::Open(const std::filesystem::path& path) {
  core::Result<Compression> compression = DetectCompression(path);
  if (!compression.ok()) return compression.status();

  std::unique_ptr<detail::ByteSource> source;
  switch (*compression) {
    case Compression::kNone: {
      core::Result<FilePtr> file = OpenFile(path);
      if (!file.ok()) return file.status();
      source = std::make_unique<PlainSource>(std::move(file).value());
      break;
    }
    case Compression::kGzip: {
      errno = 0;
      GzPtr file(gzopen(path.c_str(), "rb"));
      if (file == nullptr) {
        return core::Status::Error(path.string() + ": cannot open gzip file: " + ErrnoText());
      }
      gzbuffer(file.get(), kChunkBytes);
      source = std::make_unique<GzipSource>(std::move(file));
      break;
    }
    case Compression::kBzip2: {
      core::Result<FilePtr> file = OpenFile(path);
      if (!file.ok()) return file.status();
      auto bzip2 = std::make_unique<Bzip2Source>(std::move(file).value());
      if (core::Status started = bzip2->Start(nullptr, 0); !started.ok()) {
        return started.WithContext(path.string());
      }
      source = std::move(bzip2);
      break;
    }
  }
  return LineReader(path, *compression, std::move(source));
}

LineReader::LineReader(std::filesystem::path path, Compression compression,
                       std::unique_ptr<detail::ByteSource> source)
    : path_(std::move(path)), compression_(compression), source_(std::move(source)) {}

LineReader::LineReader(LineReader&&) noexcept = default;
LineReader& LineReader::operator=(LineReader&&) noexcept = default;
LineReader::~LineReader() = default;

bool LineReader::Refill() {
  if (source_done_ || !status_.ok()) return false;
  buffer_.erase(0, buffer_pos_);
  buffer_pos_ = 0;
  const std::size_t old_size = buffer_.size();
  buffer_.resize(old_size + kChunkBytes);
  core::Result<std::size_t> n = source_->Read(buffer_.data() + old_size, kChunkBytes);
  if (!n.ok()) {
    buffer_.resize(old_size);
    status_ =
        n.status().WithContext(path_.string() + ": after line " + std::to_string(line_number_) +
                               " (" + std::string(CompressionName(compression_)) + ")");
    return false;
  }
  buffer_.resize(old_size + *n);
  if (*n == 0) source_done_ = true;
  return *n > 0;
}

bool LineReader::ReadLine(std::string* line) {
  assert(line != nullptr);
  std::size_t search_from = buffer_pos_;
  while (true) {
    const std::size_t newline = buffer_.find('\n', search_from);
    if (newline != std::string::npos) {
      std::size_t end = newline;
      if (end > buffer_pos_ && buffer_[end - 1] == '\r') --end;
      line->assign(buffer_, buffer_pos_, end - buffer_pos_);
      buffer_pos_ = newline + 1;
      ++line_number_;
      return true;
    }
    // Refill moves the unread bytes to the front of the buffer.
    const std::size_t unread = buffer_.size() - buffer_pos_;
    if (!Refill()) break;
    search_from = unread;
  }
  if (!status_.ok() || buffer_pos_ >= buffer_.size()) return false;
  // A last line without a final newline.
  std::size_t end = buffer_.size();
  if (buffer_[end - 1] == '\r') --end;
  line->assign(buffer_, buffer_pos_, end - buffer_pos_);
  buffer_pos_ = buffer_.size();
  ++line_number_;
  return true;
}

}  // namespace groundline::io
