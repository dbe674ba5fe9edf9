#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "groundline/fleet/marginal_packet.h"
#include "packet_fixture.h"

namespace groundline::fleet {
namespace {

using Bytes = std::vector<std::uint8_t>;

// Offsets of the layout in docs/marginal_packet.md.
constexpr std::size_t kCrcOffset = 12;
constexpr std::size_t kStampOffset = 24;
constexpr std::size_t KeysOffset() { return 32; }
constexpr std::size_t PosesOffset(std::size_t n) { return 32 + 8 * n; }
constexpr std::size_t ROffset(std::size_t n) { return 32 + 32 * n; }
// Offset of R(i, j), j >= i, in the row-major upper triangle of a 3n x 3n R.
constexpr std::size_t REntryOffset(std::size_t n, std::size_t i, std::size_t j) {
  const std::size_t dim = 3 * n;
  return ROffset(n) + 8 * (i * dim - i * (i - 1) / 2 + (j - i));
}
constexpr std::size_t BOffset(std::size_t n) { return ROffset(n) + 8 * (3 * n * (3 * n + 1) / 2); }

void PutUint(Bytes* bytes, std::size_t offset, std::uint64_t value, int size) {
  for (int i = 0; i < size; ++i) (*bytes)[offset + i] = static_cast<std::uint8_t>(value >> (8 * i));
}
void PutDouble(Bytes* bytes, std::size_t offset, double value) {
  PutUint(bytes, offset, std::bit_cast<std::uint64_t>(value), 8);
}
// Rewrites the CRC so that only the deliberate change remains to be found.
void FixCrc(Bytes* bytes) { PutUint(bytes, kCrcOffset, PacketCrc32(*bytes), 4); }

void ExpectRejected(const Bytes& bytes, const std::string& fragment) {
  const core::Result<MarginalPacket> packet = Deserialize(bytes);
  ASSERT_FALSE(packet.ok()) << "accepted; expected: " << fragment;
  EXPECT_NE(packet.message().find(fragment), std::string::npos)
      << "message '" << packet.message() << "' lacks '" << fragment << "'";
}

void ExpectSamePacket(const MarginalPacket& a, const MarginalPacket& b) {
  EXPECT_EQ(a.format_version, b.format_version);
  EXPECT_EQ(a.robot_id, b.robot_id);
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.stamp_s, b.stamp_s);
  EXPECT_EQ(a.separator_keys, b.separator_keys);
  ASSERT_EQ(a.linearization_point.size(), b.linearization_point.size());
  for (std::size_t k = 0; k < a.linearization_point.size(); ++k) {
    EXPECT_EQ(a.linearization_point[k].Vector(), b.linearization_point[k].Vector());
  }
  EXPECT_EQ(a.sqrt_information, b.sqrt_information);
  EXPECT_EQ(a.residual_offset, b.residual_offset);
}

TEST(MarginalPacketWire, RoundTripIsBitExact) {
  for (std::size_t n : {1u, 2u, 7u}) {
    const MarginalPacket packet = RandomPacket(n, 100 + static_cast<std::uint32_t>(n));
    const core::Result<Bytes> bytes = Serialize(packet);
    ASSERT_TRUE(bytes.ok()) << bytes.message();
    const core::Result<MarginalPacket> back = Deserialize(*bytes);
    ASSERT_TRUE(back.ok()) << back.message();
    ExpectSamePacket(*back, packet);
    EXPECT_EQ(Serialize(*back).value(), *bytes);
  }
}

TEST(MarginalPacketWire, HeaderIsLittleEndianWithTheDocumentedFields) {
  const MarginalPacket packet = RandomPacket(2, 5);
  const Bytes bytes = Serialize(packet).value();
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "GLMP");
  EXPECT_EQ(bytes[4], 1);  // version
  EXPECT_EQ(bytes[5], 0);
  EXPECT_EQ(bytes[6], 3);      // robot id
  EXPECT_EQ(bytes[8], 2);      // n
  EXPECT_EQ(bytes[16], 0x08);  // sequence, least significant byte first
  EXPECT_EQ(bytes[23], 0x01);
  EXPECT_EQ(bytes[KeysOffset()], (1000 & 0xFF));
  EXPECT_EQ(bytes[KeysOffset() + 6], 3);  // robot id in bits 48..63 of the key
}

TEST(MarginalPacketWire, SizeFormulaMatchesTheSerializedSize) {
  EXPECT_EQ(SerializedSizeBytes(1), 136u);
  EXPECT_EQ(SerializedSizeBytes(10), 4312u);
  for (std::size_t n = 1; n <= 12; ++n) {
    EXPECT_EQ(Serialize(RandomPacket(n, 7)).value().size(), SerializedSizeBytes(n)) << n;
  }
}

TEST(MarginalPacketWire, EveryFlippedByteIsRejected) {
  const Bytes good = Serialize(RandomPacket(2, 9)).value();
  for (std::size_t i = 0; i < good.size(); ++i) {
    for (std::uint8_t mask : {0x01, 0x80, 0xFF}) {
      Bytes bytes = good;
      bytes[i] ^= mask;
      SCOPED_TRACE("byte " + std::to_string(i) + " mask " + std::to_string(mask));
      if (i < 4) {
        ExpectRejected(bytes, "bad magic");
      } else if (i < 6) {
        ExpectRejected(bytes, "unknown format version");
      } else if (i >= 8 && i < 12) {
        ExpectRejected(bytes, "size mismatch");
      } else {
        ExpectRejected(bytes, "CRC mismatch");
      }
    }
  }
}

TEST(MarginalPacketWire, TruncatedAndPaddedPacketsAreRejected) {
  const Bytes good = Serialize(RandomPacket(2, 10)).value();
  for (std::size_t size = 0; size < good.size(); ++size) {
    const Bytes bytes(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(size));
    ExpectRejected(bytes, size < 32 ? "truncated" : "size mismatch");
  }
  Bytes padded = good;
  padded.push_back(0);
  ExpectRejected(padded,
                 "size mismatch: the header declares 2 separator poses, i.e. 312 bytes, "
                 "got 313 bytes");
}

TEST(MarginalPacketWire, WrongMagicAndVersionAreNamed) {
  Bytes bytes = Serialize(RandomPacket(1, 11)).value();
  bytes[0] = 'X';
  ExpectRejected(bytes, "bad magic");
  bytes = Serialize(RandomPacket(1, 11)).value();
  PutUint(&bytes, 4, 2, 2);
  ExpectRejected(bytes, "unknown format version 2");
}

TEST(MarginalPacketWire, ContentErrorsBehindAValidCrcAreCaught) {
  constexpr std::size_t n = 3;
  const Bytes good = Serialize(RandomPacket(n, 12)).value();
  const double nan = std::numeric_limits<double>::quiet_NaN();

  Bytes bytes = good;
  PutDouble(&bytes, REntryOffset(n, 2, 6), nan);
  FixCrc(&bytes);
  ExpectRejected(bytes, "non-finite number in R(2, 6)");

  bytes = good;
  PutDouble(&bytes, BOffset(n) + 8 * 4, -std::numeric_limits<double>::infinity());
  FixCrc(&bytes);
  ExpectRejected(bytes, "non-finite number in b(4)");

  bytes = good;
  PutDouble(&bytes, kStampOffset, nan);
  FixCrc(&bytes);
  ExpectRejected(bytes, "non-finite stamp_s");

  bytes = good;
  PutDouble(&bytes, PosesOffset(n) + 24 * 1 + 8, nan);  // y of pose 1
  FixCrc(&bytes);
  ExpectRejected(bytes, "non-finite number in the linearization point of pose 1");

  bytes = good;
  PutDouble(&bytes, PosesOffset(n) + 24 * 2 + 16, 4.0);  // yaw of pose 2, not wrapped
  FixCrc(&bytes);
  ExpectRejected(bytes, "outside [-pi, pi]");

  bytes = good;
  PutUint(&bytes, KeysOffset() + 8 * 2, MakePoseKey(3, 1000), 8);  // key 2 = key 0
  FixCrc(&bytes);
  ExpectRejected(bytes, "duplicated separator key robot 3 keyframe 1000 at positions 0 and 2");

  for (double diagonal : {0.0, -1.5}) {
    bytes = good;
    PutDouble(&bytes, REntryOffset(n, 4, 4), diagonal);
    FixCrc(&bytes);
    ExpectRejected(bytes, "non-positive diagonal entry: R(4, 4)");
  }
}

TEST(MarginalPacketWire, OversizedDeclarationsAreRejectedBeforeAllocating) {
  Bytes bytes = Serialize(RandomPacket(1, 13)).value();
  PutUint(&bytes, 8, 0xFFFFFFFFu, 4);
  ExpectRejected(bytes, "size mismatch: the header declares 4294967295 separator poses");
  PutUint(&bytes, 8, 0, 4);
  ExpectRejected(bytes, "size mismatch: the header declares 0 separator poses");
}

TEST(MarginalPacketWire, SerializeRefusesInvalidPackets) {
  MarginalPacket packet = RandomPacket(2, 14);
  packet.sqrt_information(3, 1) = 0.25;
  const core::Result<Bytes> bytes = Serialize(packet);
  ASSERT_FALSE(bytes.ok());
  EXPECT_NE(bytes.message().find("not upper triangular"), std::string::npos) << bytes.message();
}

}  // namespace
}  // namespace groundline::fleet
