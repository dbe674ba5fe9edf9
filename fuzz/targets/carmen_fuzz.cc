// CARMEN logs (io/carmen.h), built three times (fuzz/CMakeLists.txt):
// FUZZ_CARMEN_COMPRESSION 0 writes the input as it is (which also feeds
// corrupt gzip/bzip2 data to the decompressors whenever it starts with their
// magic bytes), 1 gzip-compresses it and 2 bzip2-compresses it first, so the
// text inside a valid stream is fuzzed too. Each input is read leniently and
// strictly; strict mode may only reject more.
#include <bzlib.h>
#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input.h"
#include "groundline/io/carmen.h"

namespace gf = groundline::fuzz;
namespace gio = groundline::io;

namespace {

std::string Gzip(const std::uint8_t* data, std::size_t size) {
  z_stream z{};
  gf::FuzzCheck(deflateInit2(&z, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) == Z_OK,
                "deflateInit2");
  std::string out(deflateBound(&z, size) + 32, '\0');
  z.next_in = const_cast<Bytef*>(data);
  z.avail_in = static_cast<uInt>(size);
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  gf::FuzzCheck(deflate(&z, Z_FINISH) == Z_STREAM_END, "deflate");
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

std::string Bzip2(const std::uint8_t* data, std::size_t size) {
  unsigned int out_size = static_cast<unsigned int>(size + size / 100 + 700);
  std::string out(out_size, '\0');
  char* in = const_cast<char*>(reinterpret_cast<const char*>(data));
  gf::FuzzCheck(BZ2_bzBuffToBuffCompress(out.data(), &out_size, in, static_cast<unsigned int>(size),
                                         1, 0, 0) == BZ_OK,
                "BZ2_bzBuffToBuffCompress");
  out.resize(out_size);
  return out;
}

// True if `data` is a gzip or bzip2 stream that decompresses to more than
// kMaxText bytes. A few kB of such a stream expand a thousandfold (bzip2's
// run-length stage: 3 kB of corpus gave 16 MB of text), and reading that text
// twice per execution took the plain target from thousands of executions per
// second to under a hundred, all spent on lines the fuzzer already covers.
// The reader streams such a file like any long log (its tests cover long
// logs); the fuzzer skips it. Corrupt streams, which fail before the cap, are
// still read. Only the first bzip2 stream is measured.
constexpr unsigned int kMaxText = 1u << 16;

bool ExpandsPastTheCap(const std::uint8_t* data, std::size_t size) {
  std::string out(kMaxText, '\0');
  if (size >= 3 && data[0] == 'B' && data[1] == 'Z' && data[2] == 'h') {
    unsigned int out_size = kMaxText;
    return BZ2_bzBuffToBuffDecompress(out.data(), &out_size,
                                      const_cast<char*>(reinterpret_cast<const char*>(data)),
                                      static_cast<unsigned int>(size), 0, 0) == BZ_OUTBUFF_FULL;
  }
  if (size >= 2 && data[0] == 0x1f && data[1] == 0x8b) {
    z_stream z{};
    if (inflateInit2(&z, 15 + 16) != Z_OK) return false;
    z.next_in = const_cast<Bytef*>(data);
    z.avail_in = static_cast<uInt>(size);
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = kMaxText;
    const int status = inflate(&z, Z_FINISH);
    inflateEnd(&z);
    return z.avail_out == 0 && status != Z_STREAM_END;
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 20)) return 0;
  constexpr int kCompression = FUZZ_CARMEN_COMPRESSION;
  if (kCompression == 0 && ExpandsPastTheCap(data, size)) return 0;
  const auto path = kCompression == 1   ? gf::WriteInput("log.clf.gz", Gzip(data, size))
                    : kCompression == 2 ? gf::WriteInput("log.clf.bz2", Bzip2(data, size))
                                        : gf::WriteInput("log.clf", data, size);
  gio::CarmenReadOptions options;
  options.max_readings = 2000;  // keeps each execution short; the limit itself is fuzzed
  const auto lenient = gio::ReadCarmenLog(path, options);
  options.strict = true;
  const auto strict = gio::ReadCarmenLog(path, options);
  if (strict.ok()) gf::FuzzCheck(lenient.ok(), "lenient mode accepts what strict mode accepts");
  if (!lenient.ok()) gf::FuzzCheck(!lenient.message().empty(), "an error has a message");
  return 0;
}
