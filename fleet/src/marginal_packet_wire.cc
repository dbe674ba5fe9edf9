// Serialize, Deserialize and PacketCrc32 of marginal_packet.h; the layout is
// in docs/marginal_packet.md.
#include "groundline/fleet/marginal_packet.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace groundline::fleet {
namespace {

constexpr std::array<std::uint8_t, 4> kMagic = {'G', 'L', 'M', 'P'};
constexpr std::size_t kHeaderBytes = 32;
constexpr std::size_t kVersionOffset = 4;
constexpr std::size_t kRobotIdOffset = 6;
constexpr std::size_t kNumPosesOffset = 8;
constexpr std::size_t kCrcOffset = 12;
constexpr std::size_t kSequenceOffset = 16;
constexpr std::size_t kStampOffset = 24;

static_assert(SerializedSizeBytes(10) == 4312);

class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>* bytes) : bytes_(bytes) {}
  void Uint(std::uint64_t value, int num_bytes) {
    for (int i = 0; i < num_bytes; ++i)
      bytes_->push_back(static_cast<std::uint8_t>(value >> (8 * i)));
  }
  void Double(double value) { Uint(std::bit_cast<std::uint64_t>(value), 8); }

 private:
  std::vector<std::uint8_t>* bytes_;
};

std::uint64_t ReadUint(std::span<const std::uint8_t> bytes, std::size_t offset, int num_bytes) {
  std::uint64_t value = 0;
  for (int i = 0; i < num_bytes; ++i) value |= std::uint64_t{bytes[offset + i]} << (8 * i);
  return value;
}

class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, std::size_t offset)
      : bytes_(bytes), offset_(offset) {}
  std::uint64_t Uint64() {
    const std::uint64_t value = ReadUint(bytes_, offset_, 8);
    offset_ += 8;
    return value;
  }
  double Double() { return std::bit_cast<double>(Uint64()); }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t offset_;
};

std::string Hex(std::uint64_t value) {
  std::ostringstream out;
  out << "0x" << std::hex << value;
  return out.str();
}

core::Status PacketError(const std::string& what) {
  return core::Status::Error("marginal packet: " + what);
}

std::uint32_t Crc32Of(std::uint32_t crc, const std::uint8_t* data, std::size_t size) {
  return static_cast<std::uint32_t>(crc32_z(crc, data, size));
}

}  // namespace

std::uint32_t PacketCrc32(std::span<const std::uint8_t> bytes) {
  assert(bytes.size() >= kHeaderBytes);
  std::uint32_t crc = Crc32Of(0, bytes.data(), kCrcOffset);
  return Crc32Of(crc, bytes.data() + kCrcOffset + 4, bytes.size() - kCrcOffset - 4);
}

core::Result<std::vector<std::uint8_t>> Serialize(const MarginalPacket& packet) {
  if (core::Status status = packet.Validate(); !status.ok()) {
    return status.WithContext("marginal packet: cannot serialize");
  }
  const std::size_t n = packet.NumPoses();
  const auto dim = static_cast<Eigen::Index>(3 * n);
  std::vector<std::uint8_t> bytes;
  bytes.reserve(SerializedSizeBytes(n));
  Writer out(&bytes);
  bytes.insert(bytes.end(), kMagic.begin(), kMagic.end());
  out.Uint(packet.format_version, 2);
  out.Uint(packet.robot_id, 2);
  out.Uint(n, 4);
  out.Uint(0, 4);  // CRC, filled in below
  out.Uint(packet.sequence, 8);
  out.Double(packet.stamp_s);
  for (std::uint64_t key : packet.separator_keys) out.Uint(key, 8);
  for (const core::SE2& pose : packet.linearization_point) {
    out.Double(pose.x());
    out.Double(pose.y());
    out.Double(pose.yaw());
  }
  for (Eigen::Index i = 0; i < dim; ++i) {
    for (Eigen::Index j = i; j < dim; ++j) out.Double(packet.sqrt_information(i, j));
  }
  for (Eigen::Index i = 0; i < dim; ++i) out.Double(packet.residual_offset(i));
  assert(bytes.size() == SerializedSizeBytes(n));
  const std::uint32_t crc = PacketCrc32(bytes);
  for (int i = 0; i < 4; ++i) bytes[kCrcOffset + i] = static_cast<std::uint8_t>(crc >> (8 * i));
  return bytes;
}

core::Result<MarginalPacket> Deserialize(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kHeaderBytes) {
    return PacketError("truncated: " + std::to_string(bytes.size()) + " bytes, shorter than the " +
                       std::to_string(kHeaderBytes) + "-byte header");
  }
  if (!std::equal(kMagic.begin(), kMagic.end(), bytes.begin())) {
    return PacketError("bad magic " + Hex(ReadUint(bytes, 0, 4)) + " (expected 'GLMP')");
  }
  MarginalPacket packet;
  packet.format_version = static_cast<std::uint16_t>(ReadUint(bytes, kVersionOffset, 2));
  if (packet.format_version != kMarginalPacketVersion) {
    return PacketError("unknown format version " + std::to_string(packet.format_version) +
                       " (this build reads version " + std::to_string(kMarginalPacketVersion) +
                       ")");
  }
  const std::size_t n = ReadUint(bytes, kNumPosesOffset, 4);
  if (n == 0 || n > kMaxSeparatorPoses) {
    return PacketError("size mismatch: the header declares " + std::to_string(n) +
                       " separator poses, expected 1 to " + std::to_string(kMaxSeparatorPoses));
  }
  if (bytes.size() != SerializedSizeBytes(n)) {
    return PacketError("size mismatch: the header declares " + std::to_string(n) +
                       " separator poses, i.e. " + std::to_string(SerializedSizeBytes(n)) +
                       " bytes, got " + std::to_string(bytes.size()) + " bytes");
  }
  const auto stored_crc = static_cast<std::uint32_t>(ReadUint(bytes, kCrcOffset, 4));
  const std::uint32_t computed_crc = PacketCrc32(bytes);
  if (stored_crc != computed_crc) {
    return PacketError("CRC mismatch: the header holds " + Hex(stored_crc) + ", the bytes give " +
                       Hex(computed_crc) + " (corrupted in transit)");
  }
  packet.robot_id = static_cast<std::uint16_t>(ReadUint(bytes, kRobotIdOffset, 2));
  packet.sequence = ReadUint(bytes, kSequenceOffset, 8);
  Reader in(bytes, kStampOffset);
  packet.stamp_s = in.Double();
  packet.separator_keys.resize(n);
  for (std::uint64_t& key : packet.separator_keys) key = in.Uint64();
  packet.linearization_point.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double x_m = in.Double();
    const double y_m = in.Double();
    const double yaw_rad = in.Double();
    // SE2 would wrap a yaw silently; a sender always writes it wrapped.
    if (std::abs(yaw_rad) > std::numbers::pi) {
      return PacketError("the yaw of linearization pose " + std::to_string(k) + " is " +
                         std::to_string(yaw_rad) + " rad, outside [-pi, pi]");
    }
    packet.linearization_point.emplace_back(x_m, y_m, yaw_rad);
  }
  const auto dim = static_cast<Eigen::Index>(3 * n);
  packet.sqrt_information = Eigen::MatrixXd::Zero(dim, dim);
  for (Eigen::Index i = 0; i < dim; ++i) {
    for (Eigen::Index j = i; j < dim; ++j) packet.sqrt_information(i, j) = in.Double();
  }
  packet.residual_offset.resize(dim);
  for (Eigen::Index i = 0; i < dim; ++i) packet.residual_offset(i) = in.Double();
  if (core::Status status = packet.Validate(); !status.ok()) {
    return status.WithContext("marginal packet");
  }
  return packet;
}

}  // namespace groundline::fleet
