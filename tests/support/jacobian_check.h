// The one shared helper that checks analytic Jacobians against numeric
// differentiation (central differences on the manifold), in the spirit of
// gtsam's factorTesting.h and ceres' manifold_test_utils.h.
//
//   EXPECT_JACOBIAN_NEAR(J_analytic, f, x, tol);
//
// f maps an input of type In to an output of type Out. In and Out are a
// double, a fixed-size Eigen vector or core::SE2 (right perturbation,
// x (+) d = x * Exp(d)); add a ManifoldTraits specialization for new types.
// Column i of the numeric Jacobian is
//   (f(x (+) h e_i) (-) f(x (+) -h e_i)) / (2 h).
#ifndef GROUNDLINE_TESTS_SUPPORT_JACOBIAN_CHECK_H_
#define GROUNDLINE_TESTS_SUPPORT_JACOBIAN_CHECK_H_

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <utility>

#include "groundline/core/se2.h"

namespace groundline::testing {

template <typename T, typename Enable = void>
struct ManifoldTraits;

template <>
struct ManifoldTraits<double> {
  static constexpr int kDim = 1;
  static double Plus(double x, const Eigen::VectorXd& d) { return x + d(0); }
  static Eigen::VectorXd Minus(double a, double b) { return Eigen::VectorXd::Constant(1, a - b); }
};

template <typename T>
struct ManifoldTraits<T, std::enable_if_t<std::is_base_of_v<Eigen::MatrixBase<T>, T>>> {
  static_assert(T::ColsAtCompileTime == 1 && T::RowsAtCompileTime > 0,
                "Jacobian checks take fixed-size column vectors");
  static constexpr int kDim = T::RowsAtCompileTime;
  static T Plus(const T& x, const Eigen::VectorXd& d) { return x + d; }
  static Eigen::VectorXd Minus(const T& a, const T& b) { return a - b; }
};

template <>
struct ManifoldTraits<core::SE2> {
  static constexpr int kDim = 3;
  static core::SE2 Plus(const core::SE2& x, const Eigen::VectorXd& d) {
    return x.Plus(core::Vector3(d));
  }
  static Eigen::VectorXd Minus(const core::SE2& a, const core::SE2& b) { return a.Minus(b); }
};

// Numeric Jacobian of f at x by central differences with step h.
template <typename F, typename In>
Eigen::MatrixXd NumericJacobian(const F& f, const In& x, double h = 1e-6) {
  using Out = std::decay_t<decltype(f(x))>;
  constexpr int kIn = ManifoldTraits<In>::kDim;
  constexpr int kOut = ManifoldTraits<Out>::kDim;
  Eigen::MatrixXd jacobian(kOut, kIn);
  for (int i = 0; i < kIn; ++i) {
    Eigen::VectorXd step = Eigen::VectorXd::Zero(kIn);
    step(i) = h;
    const Out forward = f(ManifoldTraits<In>::Plus(x, step));
    const Out backward = f(ManifoldTraits<In>::Plus(x, -step));
    jacobian.col(i) = ManifoldTraits<Out>::Minus(forward, backward) / (2.0 * h);
  }
  return jacobian;
}

// Compares an analytic Jacobian with the numeric one, element-wise within tol
// (absolute, scaled up by max(1, |numeric|) per element).
template <typename Derived, typename F, typename In>
::testing::AssertionResult JacobianNear(const char* analytic_expr, const char* f_expr,
                                        const char* /*x_expr*/, const char* /*tol_expr*/,
                                        const Eigen::MatrixBase<Derived>& analytic, const F& f,
                                        const In& x, double tol) {
  const Eigen::MatrixXd numeric = NumericJacobian(f, x);
  if (analytic.rows() != numeric.rows() || analytic.cols() != numeric.cols()) {
    return ::testing::AssertionFailure()
           << analytic_expr << " is " << analytic.rows() << "x" << analytic.cols()
           << " but the numeric Jacobian of " << f_expr << " is " << numeric.rows() << "x"
           << numeric.cols();
  }
  double worst = 0.0;
  for (int r = 0; r < numeric.rows(); ++r) {
    for (int c = 0; c < numeric.cols(); ++c) {
      const double scale = std::max(1.0, std::abs(numeric(r, c)));
      worst = std::max(worst, std::abs(analytic(r, c) - numeric(r, c)) / scale);
    }
  }
  if (worst <= tol) return ::testing::AssertionSuccess();
  std::ostringstream out;
  out << analytic_expr << " differs from the numeric Jacobian of " << f_expr << " by " << worst
      << " (tolerance " << tol << ")\nanalytic:\n"
      << analytic << "\nnumeric:\n"
      << numeric;
  return ::testing::AssertionFailure() << out.str();
}

}  // namespace groundline::testing

#define EXPECT_JACOBIAN_NEAR(analytic, f, x, tol) \
  EXPECT_PRED_FORMAT4(::groundline::testing::JacobianNear, analytic, f, x, tol)
#define ASSERT_JACOBIAN_NEAR(analytic, f, x, tol) \
  ASSERT_PRED_FORMAT4(::groundline::testing::JacobianNear, analytic, f, x, tol)

#endif  // GROUNDLINE_TESTS_SUPPORT_JACOBIAN_CHECK_H_
