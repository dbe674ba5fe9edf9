// core/covariance.h: CovarianceAtLeast is the least upper bound that the
// header states, on random pairs and the limiting cases; DifferenceInformation
// is (C + I^-1)^-1 where I is invertible and its limit where I is singular.
#include "groundline/core/covariance.h"

#include <gtest/gtest.h>

#include <random>

namespace groundline::core {
namespace {

template <int N>
Eigen::Matrix<double, N, N> RandomCovariance(std::mt19937_64& rng) {
  std::normal_distribution<double> n01;
  Eigen::Matrix<double, N, N> a;
  for (int i = 0; i < N * N; ++i) a.data()[i] = n01(rng);
  return a * a.transpose() + 1e-3 * Eigen::Matrix<double, N, N>::Identity();
}

// The smallest eigenvalue of a symmetric matrix, relative to a scale.
template <int N>
double MinEigen(const Eigen::Matrix<double, N, N>& m) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>>(m).eigenvalues().minCoeff();
}

TEST(CovarianceAtLeast, IsAtLeastBothAndNoMoreThanNeeded) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d c = RandomCovariance<3>(rng);
    const Eigen::Matrix3d f = RandomCovariance<3>(rng);
    const Eigen::Matrix3d r = CovarianceAtLeast<3>(c, f);
    const double scale = c.norm() + f.norm();
    EXPECT_TRUE(IsCovariance<3>(r));
    EXPECT_GE(MinEigen<3>(r - c), -1e-9 * scale);
    EXPECT_GE(MinEigen<3>(r - f), -1e-9 * scale);
    // Tight: no more than the sum (which is also an upper bound of both).
    EXPECT_GE(MinEigen<3>(c + f - r), -1e-9 * scale);
    // Along every generalized eigendirection it equals one of the two.
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix3d> g(f, c);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d v = g.eigenvectors().col(k);
      const double rv = v.dot(r * v), cv = v.dot(c * v), fv = v.dot(f * v);
      EXPECT_NEAR(rv, std::max(cv, fv), 1e-8 * std::max(cv, fv));
    }
  }
}

TEST(CovarianceAtLeast, KeepsTheLargerWhenOneBoundsTheOther) {
  std::mt19937_64 rng(9);
  const Eigen::Matrix2d c = RandomCovariance<2>(rng);
  const Eigen::Matrix2d small = 0.25 * c;
  EXPECT_LT((CovarianceAtLeast<2>(c, small) - c).norm(), 1e-12 * c.norm());
  EXPECT_LT((CovarianceAtLeast<2>(small, c) - c).norm(), 1e-12 * c.norm());
  // A floor that is not finite is ignored; a c that is not positive definite
  // becomes c + floor.
  EXPECT_EQ(CovarianceAtLeast<2>(c, Eigen::Matrix2d::Constant(std::nan(""))), c);
  EXPECT_EQ(CovarianceAtLeast<2>(Eigen::Matrix2d::Zero(), c), c);
  // A floor across a thin covariance widens only that direction.
  Eigen::Matrix2d thin;
  thin << 1e-6, 0, 0, 1e-2;
  Eigen::Matrix2d across;
  across << 1e-4, 0, 0, 1e-4;
  const Eigen::Matrix2d r = CovarianceAtLeast<2>(thin, across);
  EXPECT_NEAR(r(0, 0), 1e-4, 1e-12);
  EXPECT_NEAR(r(1, 1), 1e-2, 1e-12);
  EXPECT_NEAR(r(0, 1), 0.0, 1e-12);
}

// An invertible information: the Woodbury form equals (C + I^-1)^-1 itself.
TEST(DifferenceInformation, IsTheInverseOfTheSummedCovariances) {
  std::mt19937_64 rng(17);
  for (int k = 0; k < 50; ++k) {
    const Eigen::Matrix3d C = RandomCovariance<3>(rng);
    const Eigen::Matrix3d I = RandomCovariance<3>(rng).inverse();
    const Eigen::Matrix3d expected = (C + I.inverse()).inverse();
    EXPECT_LT((DifferenceInformation<3>(C, I) - expected).norm(), 1e-9 * expected.norm());
  }
}

// A measurement blind along x (information 0 there): the distance ignores x
// and equals the limit of an ever weaker x information; it equals the 2-dof
// distance under C's y-yaw block plus the measurement's covariance.
TEST(DifferenceInformation, ASingularInformationWeighsOnlyWhatItConstrains) {
  std::mt19937_64 rng(5);
  const Eigen::Matrix3d C = RandomCovariance<3>(rng);
  Eigen::Matrix3d I = Eigen::Vector3d(0.0, 400.0, 9e4).asDiagonal();
  const Eigen::Matrix3d W = DifferenceInformation<3>(C, I);
  EXPECT_LT(W.col(0).norm(), 1e-9 * W.norm());
  const Eigen::Vector3d r(0.3, 0.01, 0.002);
  const Eigen::Matrix2d S = C.bottomRightCorner<2, 2>() +
                            Eigen::Vector2d(1.0 / 400.0, 1.0 / 9e4).asDiagonal().toDenseMatrix();
  const double expected = SquaredMahalanobis<2>(r.tail<2>(), S);
  EXPECT_NEAR(r.dot(W * r), expected, 1e-9 * expected);
  I(0, 0) = 1e-9;
  const Eigen::Matrix3d weak = (C + I.inverse()).inverse();
  EXPECT_NEAR(r.dot(weak * r), expected, 1e-6 * expected);
}

}  // namespace
}  // namespace groundline::core
