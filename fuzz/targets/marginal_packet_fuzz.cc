// The fleet's condensed marginal packets as they arrive from another vehicle
// (fleet/marginal_packet.h: Deserialize). Byte 0 of the input chooses whether
// the packet's CRC is fixed up first (bit 0), so that mutations reach the
// content checks behind it; the rest is the packet. An accepted packet passes
// Validate() and serializes back to the same bytes.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz_input.h"
#include "groundline/fleet/marginal_packet.h"

namespace gfl = groundline::fleet;
namespace gf = groundline::fuzz;

namespace {
constexpr std::size_t kHeaderBytes = 32;  // marginal_packet_wire.cc
constexpr std::size_t kCrcOffset = 12;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  std::vector<std::uint8_t> bytes(data + 1, data + size);
  if ((data[0] & 1) != 0 && bytes.size() >= kHeaderBytes) {
    const std::uint32_t crc = gfl::PacketCrc32(bytes);
    for (int i = 0; i < 4; ++i) bytes[kCrcOffset + i] = static_cast<std::uint8_t>(crc >> (8 * i));
  }
  const auto packet = gfl::Deserialize(bytes);
  if (!packet.ok()) {
    gf::FuzzCheck(!packet.message().empty(), "an error has a message");
    return 0;
  }
  gf::FuzzCheck(packet->Validate().ok(), "an accepted packet passes Validate()");
  const auto again = gfl::Serialize(*packet);
  gf::FuzzCheck(again.ok() && *again == bytes, "an accepted packet serializes to the same bytes");
  return 0;
}
