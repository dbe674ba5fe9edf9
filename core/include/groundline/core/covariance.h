// What every reader and API that takes a covariance from outside checks.
#ifndef GROUNDLINE_CORE_COVARIANCE_H_
#define GROUNDLINE_CORE_COVARIANCE_H_

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace groundline::core {

// Finite, symmetric (relative tolerance 1e-9) and numerically positive
// definite (its Cholesky factorization succeeds).
template <int N>
bool IsCovariance(const Eigen::Matrix<double, N, N>& c) {
  if (!c.allFinite() || !c.isApprox(c.transpose(), 1e-9)) return false;
  return Eigen::LLT<Eigen::Matrix<double, N, N>>(c).info() == Eigen::Success;
}

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_COVARIANCE_H_
