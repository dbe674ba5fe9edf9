// The block-tridiagonal chain solve against a dense solve of the same normal
// equations: the step, and the last block against the inverse of the newest
// pose's marginal covariance.
#include "groundline/localization/pose_chain_solver.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

namespace groundline::localization {
namespace {

// A chain system of random factors: a full-rank prior on pose 0, a random
// unary factor of rank 0..2 on some poses and a full-rank between factor
// plus, every third edge, a rank-1 one.
PoseChainSystem RandomChain(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const auto random_matrix = [&](int rows) {
    Eigen::MatrixXd J(rows, 3);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < 3; ++c) J(r, c) = normal(rng);
    }
    return J;
  };
  const auto random_vector = [&](int rows) {
    Eigen::VectorXd v(rows);
    for (int r = 0; r < rows; ++r) v(r) = normal(rng);
    return v;
  };
  PoseChainSystem system(n);
  const auto add_unary = [&](int i, const Eigen::MatrixXd& J, const Eigen::VectorXd& r) {
    system.diagonal[i] += J.transpose() * J;
    system.gradient[i] += J.transpose() * r;
  };
  add_unary(0, random_matrix(3), random_vector(3));
  for (int i = 0; i < n; ++i) {
    const int rank = i % 3;
    if (rank > 0) add_unary(i, random_matrix(rank), random_vector(rank));
    if (i == 0) continue;
    for (const int rows : {3, i % 3 == 0 ? 1 : 0}) {
      if (rows == 0) continue;
      const Eigen::MatrixXd J_a = random_matrix(rows);
      const Eigen::MatrixXd J_b = random_matrix(rows);
      const Eigen::VectorXd r = random_vector(rows);
      system.diagonal[i - 1] += J_a.transpose() * J_a;
      system.diagonal[i] += J_b.transpose() * J_b;
      system.upper[i - 1] += J_a.transpose() * J_b;
      system.gradient[i - 1] += J_a.transpose() * r;
      system.gradient[i] += J_b.transpose() * r;
    }
  }
  return system;
}

TEST(SolvePoseChain, EqualsTheDenseSolutionAndTheNewestMarginal) {
  for (const int n : {1, 2, 7, 40}) {
    const PoseChainSystem system = RandomChain(n, 17 + n);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    Eigen::VectorXd b(3 * n);
    for (int i = 0; i < n; ++i) {
      H.block<3, 3>(3 * i, 3 * i) = system.diagonal[i];
      b.segment<3>(3 * i) = system.gradient[i];
      if (i + 1 < n) {
        H.block<3, 3>(3 * i, 3 * i + 3) = system.upper[i];
        H.block<3, 3>(3 * i + 3, 3 * i) = system.upper[i].transpose();
      }
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
    const Eigen::VectorXd dense = ldlt.solve(-b);
    const Eigen::MatrixXd covariance = ldlt.solve(Eigen::MatrixXd::Identity(3 * n, 3 * n));
    const auto step = SolvePoseChain(system);
    ASSERT_TRUE(step.ok()) << step.status().message();
    ASSERT_EQ(static_cast<int>(step->delta.size()), n);
    for (int i = 0; i < n; ++i) {
      EXPECT_LT((step->delta[i] - dense.segment<3>(3 * i)).norm(), 1e-9 * (1.0 + dense.norm()))
          << "n " << n << " pose " << i;
    }
    const Eigen::Matrix3d newest_covariance = covariance.bottomRightCorner<3, 3>();
    EXPECT_LT((step->last_information * newest_covariance - Eigen::Matrix3d::Identity()).norm(),
              1e-9)
        << "n " << n;
  }
}

TEST(SolvePoseChain, APoseWithoutInformationIsAnErrorNamingIt) {
  PoseChainSystem system = RandomChain(5, 3);
  system.diagonal[3].setZero();  // pose 3: no unary and no coupling information left
  system.upper[2].setZero();
  system.upper[3].setZero();
  const auto step = SolvePoseChain(system);
  ASSERT_FALSE(step.ok());
  EXPECT_NE(step.status().message().find("pose 3 of 5"), std::string::npos)
      << step.status().message();
}

}  // namespace
}  // namespace groundline::localization
