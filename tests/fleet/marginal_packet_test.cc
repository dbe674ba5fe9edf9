#include "groundline/fleet/marginal_packet.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "packet_fixture.h"

namespace groundline::fleet {
namespace {

void ExpectInvalid(const MarginalPacket& packet, const std::string& fragment) {
  const core::Status status = packet.Validate();
  ASSERT_FALSE(status.ok()) << "expected: " << fragment;
  EXPECT_NE(status.message().find(fragment), std::string::npos)
      << "message '" << status.message() << "' lacks '" << fragment << "'";
}

TEST(PoseKey, PacksRobotAndKeyframe) {
  EXPECT_EQ(MakePoseKey(7, 123), 0x0007'0000'0000'007BULL);
  EXPECT_EQ(RobotOfKey(MakePoseKey(65535, kMaxKeyframeIndex)), 65535);
  EXPECT_EQ(KeyframeOfKey(MakePoseKey(65535, kMaxKeyframeIndex)), kMaxKeyframeIndex);
  EXPECT_EQ(RobotOfKey(MakePoseKey(1, 0)), 1);
  EXPECT_EQ(KeyframeOfKey(MakePoseKey(1, 0)), 0u);
}

TEST(SquareRootFromInformation, ReproducesTheInformationAndTheMean) {
  std::mt19937 rng(42);
  for (std::size_t n : {1u, 2u, 5u, 10u}) {
    const Eigen::MatrixXd lambda = RandomInformation(n, rng);
    const Eigen::VectorXd eta = RandomVector(3 * n, rng);
    const core::Result<SquareRootPrior> prior = SquareRootFromInformation(lambda, eta);
    ASSERT_TRUE(prior.ok()) << prior.message();
    const Eigen::MatrixXd& R = prior->sqrt_information;
    const Eigen::VectorXd& b = prior->residual_offset;
    EXPECT_TRUE(R.isUpperTriangular(0.0));
    EXPECT_GT(R.diagonal().minCoeff(), 0.0);
    EXPECT_LT((R.transpose() * R - lambda).cwiseAbs().maxCoeff(),
              1e-12 * lambda.cwiseAbs().maxCoeff());
    EXPECT_LT((R.transpose() * b + eta).norm(), 1e-12 * (1.0 + eta.norm()));
    // The prior's minimum, -R^-1 b, solves Lambda delta = eta.
    const Eigen::VectorXd delta_min = -R.triangularView<Eigen::Upper>().solve(b);
    EXPECT_LT((delta_min - lambda.lu().solve(eta)).norm(), 1e-9 * (1.0 + delta_min.norm()));
  }
}

TEST(SquareRootFromInformation, RejectsMatricesThatAreNotPositiveDefinite) {
  const Eigen::VectorXd eta = Eigen::VectorXd::Zero(3);
  Eigen::MatrixXd indefinite = Eigen::MatrixXd::Identity(3, 3);
  indefinite(1, 1) = -1.0;
  EXPECT_NE(SquareRootFromInformation(indefinite, eta).message().find("not positive definite"),
            std::string::npos);
  // Rank 2: the along-aisle direction is unconstrained.
  Eigen::MatrixXd rank_deficient = Eigen::MatrixXd::Identity(3, 3);
  rank_deficient(0, 0) = 0.0;
  EXPECT_FALSE(SquareRootFromInformation(rank_deficient, eta).ok());
  Eigen::MatrixXd nearly_singular = Eigen::MatrixXd::Identity(3, 3);
  nearly_singular(0, 0) = 1e-18;
  EXPECT_FALSE(SquareRootFromInformation(nearly_singular, eta).ok());
  Eigen::MatrixXd asymmetric = Eigen::MatrixXd::Identity(3, 3);
  asymmetric(0, 1) = 0.5;
  EXPECT_NE(SquareRootFromInformation(asymmetric, eta).message().find("not symmetric"),
            std::string::npos);
  Eigen::MatrixXd with_nan = Eigen::MatrixXd::Identity(3, 3);
  with_nan(2, 2) = std::nan("");
  EXPECT_NE(SquareRootFromInformation(with_nan, eta).message().find("non-finite"),
            std::string::npos);
}

TEST(PriorResidual, IsBAtTheLinearizationPointAndZeroAtTheMean) {
  const MarginalPacket packet = RandomPacket(4, 8);
  const Eigen::VectorXd at_x0 = PriorResidual(packet, packet.linearization_point);
  EXPECT_LT((at_x0 - packet.residual_offset).norm(), 1e-12);

  const Eigen::VectorXd delta_min =
      -packet.sqrt_information.triangularView<Eigen::Upper>().solve(packet.residual_offset);
  std::vector<core::SE2> mean;
  for (std::size_t k = 0; k < packet.NumPoses(); ++k) {
    mean.push_back(packet.linearization_point[k].Plus(delta_min.segment<3>(3 * k)));
  }
  EXPECT_LT(PriorResidual(packet, mean).norm(), 1e-9);
}

TEST(MarginalPacket, ValidateAcceptsAWellFormedPacket) {
  EXPECT_TRUE(RandomPacket(3, 1).Validate().ok());
}

TEST(MarginalPacket, ValidateNamesWhatIsWrong) {
  const MarginalPacket good = RandomPacket(3, 2);
  MarginalPacket packet = good;
  packet.format_version = 2;
  ExpectInvalid(packet, "unknown format version 2");

  packet = good;
  packet.separator_keys.clear();
  packet.linearization_point.clear();
  ExpectInvalid(packet, "no separator poses");

  packet = good;
  packet.linearization_point.pop_back();
  ExpectInvalid(packet, "linearization point has 2 poses for 3 separator keys");

  packet = good;
  packet.sqrt_information.conservativeResize(8, 9);
  ExpectInvalid(packet, "R is 8x9, expected 9x9");

  packet = good;
  packet.residual_offset.conservativeResize(8);
  ExpectInvalid(packet, "b has 8 entries");

  packet = good;
  packet.sqrt_information(4, 2) = 1e-3;
  ExpectInvalid(packet, "not upper triangular: R(4, 2)");

  packet = good;
  packet.sqrt_information(5, 5) = 0.0;
  ExpectInvalid(packet, "non-positive diagonal entry: R(5, 5)");

  packet = good;
  packet.sqrt_information(1, 7) = std::nan("");
  ExpectInvalid(packet, "non-finite number in R(1, 7)");

  packet = good;
  packet.residual_offset(6) = INFINITY;
  ExpectInvalid(packet, "non-finite number in b(6)");

  packet = good;
  packet.stamp_s = std::nan("");
  ExpectInvalid(packet, "stamp_s");

  packet = good;
  packet.linearization_point[1] = core::SE2(std::nan(""), 0.0, 0.0);
  ExpectInvalid(packet, "linearization point of pose 1 (robot 3 keyframe 1007)");

  packet = good;
  packet.separator_keys[2] = packet.separator_keys[0];
  ExpectInvalid(packet, "duplicated separator key robot 3 keyframe 1000 at positions 0 and 2");
}

}  // namespace
}  // namespace groundline::fleet
