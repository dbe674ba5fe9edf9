#include "groundline/fleet/marginal_packet.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <unordered_map>

namespace groundline::fleet {
namespace {

constexpr double kSymmetryTol = 1e-9;
constexpr double kMinReciprocalCondition = 1e-14;

core::Status Error(const std::string& message) { return core::Status::Error(message); }

std::string KeyName(std::uint64_t key) {
  return "robot " + std::to_string(RobotOfKey(key)) + " keyframe " +
         std::to_string(KeyframeOfKey(key));
}

}  // namespace

core::Status MarginalPacket::Validate() const {
  if (format_version != kMarginalPacketVersion) {
    return Error("unknown format version " + std::to_string(format_version) + " (expected " +
                 std::to_string(kMarginalPacketVersion) + ")");
  }
  const std::size_t n = NumPoses();
  if (n == 0) return Error("no separator poses (a packet needs at least one)");
  if (n > kMaxSeparatorPoses) {
    return Error(std::to_string(n) + " separator poses, more than the maximum " +
                 std::to_string(kMaxSeparatorPoses));
  }
  const auto dim = static_cast<Eigen::Index>(3 * n);
  if (linearization_point.size() != n) {
    return Error("linearization point has " + std::to_string(linearization_point.size()) +
                 " poses for " + std::to_string(n) + " separator keys");
  }
  if (sqrt_information.rows() != dim || sqrt_information.cols() != dim) {
    return Error("R is " + std::to_string(sqrt_information.rows()) + "x" +
                 std::to_string(sqrt_information.cols()) + ", expected " + std::to_string(dim) +
                 "x" + std::to_string(dim) + " for " + std::to_string(n) + " poses");
  }
  if (residual_offset.size() != dim) {
    return Error("b has " + std::to_string(residual_offset.size()) + " entries, expected " +
                 std::to_string(dim));
  }
  if (!std::isfinite(stamp_s)) return Error("non-finite stamp_s");
  for (std::size_t k = 0; k < n; ++k) {
    if (!linearization_point[k].Vector().allFinite()) {
      return Error("non-finite number in the linearization point of pose " + std::to_string(k) +
                   " (" + KeyName(separator_keys[k]) + ")");
    }
  }
  for (Eigen::Index i = 0; i < dim; ++i) {
    for (Eigen::Index j = 0; j < dim; ++j) {
      const double value = sqrt_information(i, j);
      const std::string where = "R(" + std::to_string(i) + ", " + std::to_string(j) + ")";
      if (!std::isfinite(value)) return Error("non-finite number in " + where);
      if (j < i && value != 0.0) return Error("R is not upper triangular: " + where + " != 0");
      if (j == i && !(value > 0.0)) {
        return Error("R has a non-positive diagonal entry: " + where + " = " +
                     std::to_string(value) + " (the prior must be positive definite)");
      }
    }
    if (!std::isfinite(residual_offset(i))) {
      return Error("non-finite number in b(" + std::to_string(i) + ")");
    }
  }
  std::unordered_map<std::uint64_t, std::size_t> first_position;
  for (std::size_t k = 0; k < n; ++k) {
    const auto [it, inserted] = first_position.emplace(separator_keys[k], k);
    if (!inserted) {
      return Error("duplicated separator key " + KeyName(separator_keys[k]) + " at positions " +
                   std::to_string(it->second) + " and " + std::to_string(k));
    }
  }
  return core::Status::Ok();
}

core::Result<SquareRootPrior> SquareRootFromInformation(const Eigen::MatrixXd& information,
                                                        const Eigen::VectorXd& information_vector) {
  assert(information.rows() == information.cols());
  assert(information.rows() % 3 == 0);
  assert(information_vector.size() == information.rows());
  if (!information.allFinite() || !information_vector.allFinite()) {
    return Error(
        "SquareRootFromInformation: non-finite entries in the information matrix or "
        "vector");
  }
  const double scale = std::max(1.0, information.cwiseAbs().maxCoeff());
  const double asymmetry = (information - information.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > kSymmetryTol * scale) {
    return Error(
        "SquareRootFromInformation: the information matrix is not symmetric (max |L - "
        "L^T| = " +
        std::to_string(asymmetry) + ")");
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (information + information.transpose()));
  if (llt.info() != Eigen::Success) {
    return Error(
        "SquareRootFromInformation: the information matrix is not positive definite "
        "(Cholesky failed); the separator is not fully constrained");
  }
  const double rcond = llt.rcond();
  if (!(rcond >= kMinReciprocalCondition)) {
    std::ostringstream out;
    out << "SquareRootFromInformation: the information matrix is numerically singular "
        << "(reciprocal condition number " << rcond << ")";
    return Error(out.str());
  }
  SquareRootPrior prior;
  prior.sqrt_information = llt.matrixU();
  // R^T b = -eta with R^T = L lower triangular.
  prior.residual_offset = -llt.matrixL().solve(information_vector);
  return prior;
}

Eigen::VectorXd PriorResidual(const MarginalPacket& packet, std::span<const core::SE2> poses) {
  const std::size_t n = packet.NumPoses();
  assert(poses.size() == n);
  Eigen::VectorXd delta(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    delta.segment<3>(static_cast<Eigen::Index>(3 * k)) =
        poses[k].Minus(packet.linearization_point[k]);
  }
  return packet.sqrt_information.triangularView<Eigen::Upper>() * delta + packet.residual_offset;
}

}  // namespace groundline::fleet
