// What every reader and API that takes a covariance from outside checks.
#ifndef GROUNDLINE_CORE_COVARIANCE_H_
#define GROUNDLINE_CORE_COVARIANCE_H_

#include <Eigen/Cholesky>
#include <Eigen/Core>
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

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_COVARIANCE_H_
