// Condensed marginal packets: what one robot tells its neighbours about its
// separator poses, instead of raw data (seed paper eqs. 57-61, Schur
// condensation). The wire layout is in docs/marginal_packet.md.
//
// Meaning. A packet carries a Gaussian prior over n separator poses x_k in
// SE(2), linearized at x0_k, in square-root form:
//
//   cost(x) = 0.5 || R delta + b ||^2,   delta = (x_1 (-) x0_1, ..., x_n (-) x0_n),
//
// where x (-) x0 = Log(x0^-1 x) is the right-perturbation tangent vector
// (core::SE2::Minus, order (dx_m, dy_m, dtheta_rad)), stacked in the order of
// separator_keys, R is 3n x 3n upper triangular with a positive diagonal and b
// has 3n entries (unitless: residuals already whitened). Expanding,
//
//   cost = 0.5 delta^T Lambda delta - eta^T delta + const,
//   Lambda = R^T R,   eta = -R^T b,
//
// so Lambda is the marginal information (eq. 60) and eta the information vector
// (eq. 61, the right-hand side of Lambda delta = eta); the prior's mean is
// x0 (+) Lambda^-1 eta = x0 (+) (-R^-1 b). SquareRootFromInformation builds R and
// b from (Lambda, eta).
//
// Pose keys. A separator key packs the robot that owns the pose and the index
// of its keyframe: key = robot_id << 48 | keyframe_index (16 + 48 bits).
//
// All functions are pure and thread-safe.
#ifndef GROUNDLINE_FLEET_MARGINAL_PACKET_H_
#define GROUNDLINE_FLEET_MARGINAL_PACKET_H_

#include <Eigen/Core>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::fleet {

inline constexpr int kKeyframeIndexBits = 48;
inline constexpr std::uint64_t kMaxKeyframeIndex = (std::uint64_t{1} << kKeyframeIndexBits) - 1;

constexpr std::uint64_t MakePoseKey(std::uint16_t robot_id, std::uint64_t keyframe_index) {
  assert(keyframe_index <= kMaxKeyframeIndex);
  return (std::uint64_t{robot_id} << kKeyframeIndexBits) | keyframe_index;
}
constexpr std::uint16_t RobotOfKey(std::uint64_t key) {
  return static_cast<std::uint16_t>(key >> kKeyframeIndexBits);
}
constexpr std::uint64_t KeyframeOfKey(std::uint64_t key) { return key & kMaxKeyframeIndex; }

inline constexpr std::uint16_t kMarginalPacketVersion = 1;
// The largest separator a packet may carry (bounds allocation on reading;
// 1024 poses are 37.8 MB, far beyond any radio budget).
inline constexpr std::size_t kMaxSeparatorPoses = 1024;

struct MarginalPacket {
  std::uint16_t format_version = kMarginalPacketVersion;
  std::uint16_t robot_id = 0;                  // the sender
  std::uint64_t sequence = 0;                  // the sender's packet counter
  double stamp_s = 0.0;                        // time of the linearization, sender clock, seconds
  std::vector<std::uint64_t> separator_keys;   // n distinct keys (MakePoseKey)
  std::vector<core::SE2> linearization_point;  // x0, T_map_base per key
  Eigen::MatrixXd sqrt_information;            // R, 3n x 3n upper triangular
  Eigen::VectorXd residual_offset;             // b, 3n

  std::size_t NumPoses() const { return separator_keys.size(); }

  // Ok when the packet is well formed: known version, 1 <= n <= kMaxSeparatorPoses,
  // consistent sizes, finite numbers, R upper triangular with a positive diagonal,
  // distinct keys. The message says what is wrong and where.
  core::Status Validate() const;
};

// R and b of a Gaussian prior in square-root form.
struct SquareRootPrior {
  Eigen::MatrixXd sqrt_information;  // R, upper triangular, R^T R = Lambda
  Eigen::VectorXd residual_offset;   // b = -R^-T eta
};

// Square-root form of the prior with information Lambda (3n x 3n) and
// information vector eta (3n) (see the file comment), by Cholesky
// factorization Lambda = R^T R. Sizes must agree and be multiples of 3
// (asserted). Fails when Lambda or eta has non-finite entries, Lambda is not
// symmetric (relative tolerance 1e-9) or not numerically positive definite
// (a Cholesky pivot <= 0 or reciprocal condition number below 1e-14).
core::Result<SquareRootPrior> SquareRootFromInformation(const Eigen::MatrixXd& information,
                                                        const Eigen::VectorXd& information_vector);

// The whitened prior residual R delta + b at the poses x (one per separator
// key, in key order; size asserted). Its half squared norm is the cost.
Eigen::VectorXd PriorResidual(const MarginalPacket& packet, std::span<const core::SE2> poses);

// Bytes of a serialized packet with n separator poses:
// 32 (header) + 8n (keys) + 24n (poses) + 8 * 3n(3n+1)/2 (upper triangle of R)
// + 24n (b) = 32 + 68n + 36n^2; e.g. 4312 bytes for n = 10.
constexpr std::size_t SerializedSizeBytes(std::size_t num_poses) {
  const std::size_t dim = 3 * num_poses;
  return 32 + 8 * num_poses + 24 * num_poses + 8 * (dim * (dim + 1) / 2) + 8 * dim;
}

// The little-endian wire form of a valid packet; fails with Validate()'s message.
core::Result<std::vector<std::uint8_t>> Serialize(const MarginalPacket& packet);

// Reads a packet, checking in this order: header length, magic, version,
// declared size, CRC, then the content (Validate()). The message names the
// first problem found (e.g. "marginal packet: CRC mismatch: ...").
core::Result<MarginalPacket> Deserialize(std::span<const std::uint8_t> bytes);

// The CRC-32 (zlib / IEEE 802.3) a packet's header must hold: over all its
// bytes except the 4-byte CRC field itself. bytes must hold at least the header.
std::uint32_t PacketCrc32(std::span<const std::uint8_t> bytes);

}  // namespace groundline::fleet

#endif  // GROUNDLINE_FLEET_MARGINAL_PACKET_H_
