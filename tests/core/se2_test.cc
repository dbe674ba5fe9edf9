#include "groundline/core/se2.h"

#include <gtest/gtest.h>

#include <numbers>

#include "jacobian_check.h"

namespace groundline::core {
namespace {

TEST(SE2, ComposeWithInverseIsIdentity) {
  const SE2 t(1.5, -2.0, 2.9);
  EXPECT_TRUE((t * t.Inverse()).IsApprox(SE2::Identity(), 1e-12, 1e-12));
}

TEST(SE2, ExpJacobianMatchesNumeric) {
  const Vector3 xi(0.3, -1.2, std::numbers::pi - 1e-3);
  Matrix3 J;
  SE2::Exp(xi, &J);
  EXPECT_JACOBIAN_NEAR(J, [](const Vector3& v) { return SE2::Exp(v); }, xi, 1e-6);
}

}  // namespace
}  // namespace groundline::core
