#include "fuzz_input.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <system_error>

namespace groundline::fuzz {
namespace {

void RemoveScratchDir() {
  std::error_code ec;
  std::filesystem::remove_all(ScratchDir(), ec);
}

}  // namespace

const std::filesystem::path& ScratchDir() {
  // Never destroyed: the atexit handler is registered while this static is
  // made, so it would run after the static's own destructor and find it gone.
  static const std::filesystem::path* const dir = [] {
    // /dev/shm (memory) when there is one: a disk-backed /tmp costs ~1 ms per
    // input written, ten times the parse.
    std::error_code ec;
    std::filesystem::path base = std::filesystem::temp_directory_path();
    if (std::filesystem::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0) {
      base = "/dev/shm";
    }
    // libFuzzer ends with _Exit (no atexit handler runs): remove the
    // directories of processes that are gone before making this one.
    const std::string prefix = "groundline-fuzz-";
    for (const auto& entry : std::filesystem::directory_iterator(base, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind(prefix, 0) != 0) continue;
      const long pid = std::strtol(name.c_str() + prefix.size(), nullptr, 10);
      if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
        std::error_code ignored;
        std::filesystem::remove_all(entry.path(), ignored);
      }
    }
    const std::filesystem::path d = base / (prefix + std::to_string(::getpid()));
    std::filesystem::create_directories(d, ec);
    if (ec) {
      std::fprintf(stderr, "fuzz: cannot create %s: %s\n", d.c_str(), ec.message().c_str());
      std::abort();
    }
    std::atexit(RemoveScratchDir);
    return new std::filesystem::path(d);
  }();
  return *dir;
}

std::filesystem::path WriteInput(std::string_view name, const std::uint8_t* data,
                                 std::size_t size) {
  return WriteInput(name, std::string_view(reinterpret_cast<const char*>(data), size));
}

std::filesystem::path WriteInput(std::string_view name, std::string_view bytes) {
  const std::filesystem::path path = ScratchDir() / std::filesystem::path(name);
  std::error_code ec;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

void FuzzCheck(bool condition, std::string_view what) {
  if (condition) return;
  std::fprintf(stderr, "fuzz: contract broken: %.*s\n", static_cast<int>(what.size()), what.data());
  std::abort();
}

}  // namespace groundline::fuzz
