#include "groundline/io/compressed_file.h"

#include <bzlib.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "test_data.h"

namespace groundline::io {
namespace {

namespace fs = std::filesystem;
using groundline::testing::ScratchDir;

// The text every backend must return line for line: CRLF, an empty line,
// inner whitespace, a line longer than the reader's 64 KiB chunk, and a last
// line without a final newline.
std::string Content() {
  return "first line\nsecond line with CRLF\r\n\n  spaced\tfields  \n" + std::string(200000, 'x') +
         "\nlast line without newline";
}
std::vector<std::string> ExpectedLines() {
  return {"first line",         "second line with CRLF",  "",
          "  spaced\tfields  ", std::string(200000, 'x'), "last line without newline"};
}

void WritePlain(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good());
}

// Writes `parts` as consecutive gzip members (one member per part).
void WriteGzip(const fs::path& path, const std::vector<std::string>& parts) {
  fs::remove(path);
  for (const std::string& part : parts) {
    gzFile file = gzopen(path.c_str(), "ab");
    ASSERT_NE(file, nullptr);
    ASSERT_EQ(gzwrite(file, part.data(), static_cast<unsigned>(part.size())),
              static_cast<int>(part.size()));
    ASSERT_EQ(gzclose(file), Z_OK);
  }
}

// Writes `parts` as consecutive bzip2 streams (one stream per part).
void WriteBzip2(const fs::path& path, const std::vector<std::string>& parts) {
  fs::remove(path);
  for (const std::string& part : parts) {
    std::FILE* file = std::fopen(path.c_str(), "ab");
    ASSERT_NE(file, nullptr);
    int error = BZ_OK;
    BZFILE* bz = BZ2_bzWriteOpen(&error, file, 9, 0, 0);
    ASSERT_EQ(error, BZ_OK);
    BZ2_bzWrite(&error, bz, const_cast<char*>(part.data()), static_cast<int>(part.size()));
    ASSERT_EQ(error, BZ_OK);
    BZ2_bzWriteClose(&error, bz, 0, nullptr, nullptr);
    ASSERT_EQ(error, BZ_OK);
    std::fclose(file);
  }
}

using ::groundline::testing::ReadText;

// Reads every line, checking the line counter on the way.
std::vector<std::string> ReadAll(LineReader* reader) {
  std::vector<std::string> lines;
  std::string line;
  while (reader->ReadLine(&line)) {
    lines.push_back(line);
    EXPECT_EQ(reader->line_number(), static_cast<int64_t>(lines.size()));
  }
  return lines;
}

TEST(LineReader, SameLinesFromPlainGzipAndBzip2DetectedByMagicNotName) {
  const fs::path dir = ScratchDir("formats");
  // Misleading names on purpose: detection must use the bytes.
  const fs::path plain = dir / "plain.gz";
  const fs::path gzip = dir / "gzip.bz2";
  const fs::path bzip2 = dir / "bzip2.txt";
  WritePlain(plain, Content());
  WriteGzip(gzip, {Content()});
  WriteBzip2(bzip2, {Content()});

  const std::vector<std::pair<fs::path, Compression>> cases = {
      {plain, Compression::kNone}, {gzip, Compression::kGzip}, {bzip2, Compression::kBzip2}};
  for (const auto& [path, compression] : cases) {
    SCOPED_TRACE(path.string());
    core::Result<LineReader> reader = LineReader::Open(path);
    ASSERT_TRUE(reader.ok()) << reader.message();
    EXPECT_EQ(reader->compression(), compression);
    EXPECT_EQ(reader->path(), path);
    EXPECT_EQ(reader->line_number(), 0);
    EXPECT_EQ(ReadAll(&*reader), ExpectedLines());
    EXPECT_TRUE(reader->status().ok()) << reader->status().message();
    std::string line = "unchanged";
    EXPECT_FALSE(reader->ReadLine(&line));  // stays at the end
    EXPECT_EQ(reader->line_number(), 6);
  }
}

TEST(LineReader, ConcatenatedGzipMembersAndBzip2StreamsReadAsOneText) {
  const fs::path dir = ScratchDir("concat");
  // The split falls inside a line: the line must come out whole.
  const std::string text = Content();
  const std::vector<std::string> parts = {text.substr(0, 15), text.substr(15, 70000),
                                          text.substr(70015)};
  WriteGzip(dir / "multi.gz", parts);
  WriteBzip2(dir / "multi.bz2", parts);
  for (const char* name : {"multi.gz", "multi.bz2"}) {
    SCOPED_TRACE(name);
    core::Result<LineReader> reader = LineReader::Open(dir / name);
    ASSERT_TRUE(reader.ok()) << reader.message();
    EXPECT_EQ(ReadAll(&*reader), ExpectedLines());
    EXPECT_TRUE(reader->status().ok()) << reader->status().message();
  }
}

TEST(LineReader, TruncatedCompressedFilesFailNamingTheFile) {
  const fs::path dir = ScratchDir("truncated");
  WriteGzip(dir / "full.gz", {Content()});
  WriteBzip2(dir / "full.bz2", {Content()});
  for (const char* name : {"full.gz", "full.bz2"}) {
    SCOPED_TRACE(name);
    const std::string bytes = ReadText(dir / name);
    ASSERT_GT(bytes.size(), 100u);
    const fs::path cut = dir / (std::string("cut_") + name);
    WritePlain(cut, bytes.substr(0, bytes.size() / 2));
    core::Result<LineReader> reader = LineReader::Open(cut);
    ASSERT_TRUE(reader.ok()) << reader.message();
    ReadAll(&*reader);
    ASSERT_FALSE(reader->status().ok());
    EXPECT_NE(reader->status().message().find(cut.string()), std::string::npos)
        << reader->status().message();
    EXPECT_NE(reader->status().message().find("truncated"), std::string::npos)
        << reader->status().message();
  }
}

TEST(LineReader, CorruptBzip2DataFails) {
  const fs::path dir = ScratchDir("corrupt");
  WriteBzip2(dir / "full.bz2", {Content()});
  std::string bytes = ReadText(dir / "full.bz2");
  for (std::size_t i = 20; i < 60; ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  WritePlain(dir / "corrupt.bz2", bytes);
  core::Result<LineReader> reader = LineReader::Open(dir / "corrupt.bz2");
  ASSERT_TRUE(reader.ok()) << reader.message();
  ReadAll(&*reader);
  ASSERT_FALSE(reader->status().ok());
  EXPECT_NE(reader->status().message().find("corrupt.bz2"), std::string::npos);
}

TEST(LineReader, TrailingGarbageAfterBzip2StreamIsIgnoredLikeTheBzip2Tool) {
  const fs::path dir = ScratchDir("garbage");
  WriteBzip2(dir / "clean.bz2", {"a\nb\n"});
  WritePlain(dir / "garbage.bz2", ReadText(dir / "clean.bz2") + "not bzip2 data");
  core::Result<LineReader> reader = LineReader::Open(dir / "garbage.bz2");
  ASSERT_TRUE(reader.ok()) << reader.message();
  EXPECT_EQ(ReadAll(&*reader), (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(reader->status().ok()) << reader->status().message();
}

TEST(LineReader, EmptyAndTinyFilesArePlain) {
  const fs::path dir = ScratchDir("tiny");
  WritePlain(dir / "empty", "");
  WritePlain(dir / "one_byte", "B");  // shorter than any magic number
  core::Result<LineReader> empty = LineReader::Open(dir / "empty");
  ASSERT_TRUE(empty.ok()) << empty.message();
  EXPECT_EQ(empty->compression(), Compression::kNone);
  EXPECT_TRUE(ReadAll(&*empty).empty());
  EXPECT_TRUE(empty->status().ok());
  core::Result<LineReader> one = LineReader::Open(dir / "one_byte");
  ASSERT_TRUE(one.ok()) << one.message();
  EXPECT_EQ(ReadAll(&*one), std::vector<std::string>{"B"});
}

TEST(LineReader, MissingFileIsAnErrorNamingIt) {
  const fs::path missing = ScratchDir("missing") / "no_such.clf.bz2";
  core::Result<LineReader> reader = LineReader::Open(missing);
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.message().find(missing.string()), std::string::npos) << reader.message();
  EXPECT_FALSE(DetectCompression(missing).ok());
}

TEST(LineReader, MovedReaderContinuesWhereTheOriginalStopped) {
  const fs::path dir = ScratchDir("move");
  WriteBzip2(dir / "log.bz2", {"one\ntwo\nthree\n"});
  core::Result<LineReader> opened = LineReader::Open(dir / "log.bz2");
  ASSERT_TRUE(opened.ok()) << opened.message();
  std::string line;
  ASSERT_TRUE(opened->ReadLine(&line));
  LineReader moved = std::move(opened).value();
  ASSERT_TRUE(moved.ReadLine(&line));
  EXPECT_EQ(line, "two");
  EXPECT_EQ(moved.line_number(), 2);
}

}  // namespace
}  // namespace groundline::io
