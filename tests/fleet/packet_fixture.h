// A random, valid marginal packet for the fleet tests.
#ifndef GROUNDLINE_TESTS_FLEET_PACKET_FIXTURE_H_
#define GROUNDLINE_TESTS_FLEET_PACKET_FIXTURE_H_

#include <numbers>
#include <random>

#include "groundline/core/random_draws.h"
#include "groundline/fleet/marginal_packet.h"

namespace groundline::fleet {

// Information Lambda = A^T A + 0.1 I (positive definite) of size 3n.
inline Eigen::MatrixXd RandomInformation(std::size_t n, std::mt19937& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto dim = static_cast<Eigen::Index>(3 * n);
  Eigen::MatrixXd a(dim + 2, dim);
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = 0; j < a.cols(); ++j) a(i, j) = gauss(rng);
  }
  return a.transpose() * a + 0.1 * Eigen::MatrixXd::Identity(dim, dim);
}

inline Eigen::VectorXd RandomVector(std::size_t size, std::mt19937& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  Eigen::VectorXd v(static_cast<Eigen::Index>(size));
  for (Eigen::Index i = 0; i < v.size(); ++i) v(i) = gauss(rng);
  return v;
}

inline MarginalPacket RandomPacket(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  MarginalPacket packet;
  packet.robot_id = 3;
  packet.sequence = 0x0102030405060708ULL;
  packet.stamp_s = 1718000000.125;
  for (std::size_t k = 0; k < n; ++k) {
    packet.separator_keys.push_back(MakePoseKey(3, 1000 + 7 * k));
    const Eigen::Vector3d d = core::DrawVector<3>(unit, rng);
    packet.linearization_point.emplace_back(50.0 * d(0), 20.0 * d(1), std::numbers::pi * d(2));
  }
  const SquareRootPrior prior =
      SquareRootFromInformation(RandomInformation(n, rng), RandomVector(3 * n, rng)).value();
  packet.sqrt_information = prior.sqrt_information;
  packet.residual_offset = prior.residual_offset;
  return packet;
}

}  // namespace groundline::fleet

#endif  // GROUNDLINE_TESTS_FLEET_PACKET_FIXTURE_H_
