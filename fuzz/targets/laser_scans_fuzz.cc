// lidar_scans.txt (core/dataset_records.h): the whole-file reader and the
// streaming LaserScanReader must agree on every input.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "groundline/core/dataset_records.h"

namespace gc = groundline::core;
namespace gf = groundline::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = gf::WriteInput("lidar_scans.txt", data, size);
  const auto scans = gc::ReadLaserScans(path);
  auto reader = gc::LaserScanReader::Open(path);
  bool stream_ok = reader.ok();
  std::size_t streamed = 0;
  if (stream_ok) {
    gc::LaserScan scan;
    for (;;) {
      const auto more = reader->Next(&scan);
      if (!more.ok()) {
        stream_ok = false;
        break;
      }
      if (!*more) break;
      ++streamed;
    }
  }
  gf::FuzzCheck(stream_ok == scans.ok(), "LaserScanReader accepts what ReadLaserScans accepts");
  if (scans.ok()) gf::FuzzCheck(streamed == scans->size(), "both readers read the same scans");
  return 0;
}
