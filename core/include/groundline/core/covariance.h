// What every reader and API that takes a covariance from outside checks.
#ifndef GROUNDLINE_CORE_COVARIANCE_H_
#define GROUNDLINE_CORE_COVARIANCE_H_

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <limits>

namespace groundline::core {

// Finite, symmetric (relative tolerance 1e-9) and numerically positive
// definite (its Cholesky factorization succeeds).
template <int N>
bool IsCovariance(const Eigen::Matrix<double, N, N>& c) {
  if (!c.allFinite() || !c.isApprox(c.transpose(), 1e-9)) return false;
  return Eigen::LLT<Eigen::Matrix<double, N, N>>(c).info() == Eigen::Success;
}

// r^T S^-1 r, the squared Mahalanobis distance of r under covariance S
// (LDLT); infinity when S is not numerically positive semi-definite.
template <int N>
double SquaredMahalanobis(const Eigen::Matrix<double, N, 1>& r,
                          const Eigen::Matrix<double, N, N>& S) {
  const Eigen::LDLT<Eigen::Matrix<double, N, N>> ldlt(S);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
    return std::numeric_limits<double>::infinity();
  }
  return r.dot(ldlt.solve(r));
}

// The information of the difference between two estimates of one quantity,
// one with covariance C (positive definite) and one with information I
// (positive semi-definite: a measurement blind in some directions has a
// singular one): (C + I^+)^-1 in the directions I constrains, written by
// Woodbury as I - I (C^-1 + I)^-1 I so that no inverse of I is needed. The
// squared Mahalanobis distance of their difference r is r^T W r, with
// rank(I) degrees of freedom.
template <int N>
Eigen::Matrix<double, N, N> DifferenceInformation(const Eigen::Matrix<double, N, N>& C,
                                                  const Eigen::Matrix<double, N, N>& I) {
  using Matrix = Eigen::Matrix<double, N, N>;
  const Matrix inner = C.inverse() + I;
  const Matrix W = I - I * inner.ldlt().solve(I);
  return 0.5 * (W + W.transpose());
}

// The covariance c raised to at least `floor`: the smallest covariance in the
// generalized-eigenvector sense that is >= both (c and floor in the Loewner
// order). With c = L L^T and L^-1 floor L^-T = V D V^T, it is
// L V max(D, 1) V^T L^T: along each direction where floor exceeds c the
// variance becomes floor's, elsewhere c's stays. c itself when c >= floor;
// floor when floor >= c. A floor that is not finite is ignored; a c that is
// not positive definite is replaced by c + floor.
template <int N>
Eigen::Matrix<double, N, N> CovarianceAtLeast(const Eigen::Matrix<double, N, N>& c,
                                              const Eigen::Matrix<double, N, N>& floor) {
  using Matrix = Eigen::Matrix<double, N, N>;
  if (!floor.allFinite()) return c;
  const Eigen::LLT<Matrix> llt(c);
  if (!c.allFinite() || llt.info() != Eigen::Success) return c + floor;
  const Matrix L = llt.matrixL();
  const Matrix Linv_F = L.template triangularView<Eigen::Lower>().solve(floor);
  const Matrix M = L.template triangularView<Eigen::Lower>().solve(Linv_F.transpose());
  const Eigen::SelfAdjointEigenSolver<Matrix> eig(0.5 * (M + M.transpose()));
  const Eigen::Matrix<double, N, 1> d = eig.eigenvalues().cwiseMax(1.0);
  const Matrix LV = L * eig.eigenvectors();
  const Matrix out = LV * d.asDiagonal() * LV.transpose();
  return 0.5 * (out + out.transpose());
}

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_COVARIANCE_H_
