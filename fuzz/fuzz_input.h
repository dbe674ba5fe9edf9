// Helpers shared by the fuzz targets (fuzz/targets/*.cc).
//
// Most of groundline's readers take a path, as the tools call them. A target
// hands them its input through a file in a private scratch directory
// (/dev/shm/groundline-fuzz-<pid>/, or under $TMPDIR without /dev/shm;
// removed at exit), so the bytes fuzzed are the
// bytes the reader sees, through the same open/read/close code as in use.
//
// A finding is either a sanitizer report, an uncaught exception (libFuzzer
// reports it as a crash: no reader may let one escape), or a broken reader
// contract, reported through FuzzCheck.
#ifndef GROUNDLINE_FUZZ_FUZZ_INPUT_H_
#define GROUNDLINE_FUZZ_FUZZ_INPUT_H_

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace groundline::fuzz {

// The scratch directory of this process (created on first use).
const std::filesystem::path& ScratchDir();

// Writes `size` bytes to ScratchDir()/name (replacing it) and returns the path.
// Aborts if the file cannot be written: a broken scratch directory would make
// every later input look rejected.
std::filesystem::path WriteInput(std::string_view name, const std::uint8_t* data, std::size_t size);
std::filesystem::path WriteInput(std::string_view name, std::string_view bytes);

// The input as text (the in-memory parsers take std::string).
inline std::string AsText(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Aborts with `what` when `condition` is false: a contract the reader states
// in its header (e.g. "an accepted file passes Validate()") does not hold.
void FuzzCheck(bool condition, std::string_view what);

}  // namespace groundline::fuzz

#endif  // GROUNDLINE_FUZZ_FUZZ_INPUT_H_
