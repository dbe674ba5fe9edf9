// ManifoldTraits for HesseLine, so that EXPECT_JACOBIAN_NEAR can differentiate
// functions of lines: plus adds to (rho, alpha) without normalizing, minus is
// LineDifference (continuous across the (rho, alpha) ~ (-rho, alpha + pi) flip).
#ifndef GROUNDLINE_TESTS_PERCEPTION_HESSE_LINE_TRAITS_H_
#define GROUNDLINE_TESTS_PERCEPTION_HESSE_LINE_TRAITS_H_

#include "groundline/perception/hesse_line.h"
#include "jacobian_check.h"

namespace groundline::testing {

template <>
struct ManifoldTraits<perception::HesseLine> {
  static constexpr int kDim = 2;
  static perception::HesseLine Plus(const perception::HesseLine& line, const Eigen::VectorXd& d) {
    return {line.rho_m + d(0), line.alpha_rad + d(1)};
  }
  static Eigen::VectorXd Minus(const perception::HesseLine& a, const perception::HesseLine& b) {
    return perception::LineDifference(a, b);
  }
};

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_PERCEPTION_HESSE_LINE_TRAITS_H_
