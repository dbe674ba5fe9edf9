#include "groundline/core/se2_manifold.h"

#include <Eigen/Core>
#include <cmath>

#include "groundline/core/se2.h"

namespace groundline::core {
namespace {

using RowMajorMatrix3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using RowMajorMatrixX3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

SE2 FromAmbient(const double* x) { return SE2(x[0], x[1], x[2]); }

// [R 0; 0 1]: the ambient change of (x, y, yaw) for a right step in the
// tangent space at yaw.
RowMajorMatrix3 BlockRotation(double yaw_rad) {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  RowMajorMatrix3 m;
  m << c, -s, 0.0,  //
      s, c, 0.0,    //
      0.0, 0.0, 1.0;
  return m;
}

}  // namespace

bool SE2Manifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const SE2 out = FromAmbient(x).Plus(Vector3(delta[0], delta[1], delta[2]));
  Eigen::Map<Vector3> out_map(x_plus_delta);
  out_map = out.Vector();
  return true;
}

bool SE2Manifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<RowMajorMatrix3> j(jacobian);
  j = BlockRotation(x[2]);
  return true;
}

bool SE2Manifold::RightMultiplyByPlusJacobian(const double* x, int num_rows,
                                              const double* ambient_matrix,
                                              double* tangent_matrix) const {
  // Called by Ceres for every Jacobian block each iteration: avoid the
  // generic dense product of the base class.
  // No rows: Ceres may pass null matrices, and a column of a Map on null is
  // an offset from a null pointer (undefined behaviour).
  if (num_rows == 0) return true;
  const Eigen::Map<const RowMajorMatrixX3> in(ambient_matrix, num_rows, 3);
  Eigen::Map<RowMajorMatrixX3> out(tangent_matrix, num_rows, 3);
  const double c = std::cos(x[2]);
  const double s = std::sin(x[2]);
  out.col(0) = c * in.col(0) + s * in.col(1);
  out.col(1) = -s * in.col(0) + c * in.col(1);
  out.col(2) = in.col(2);
  return true;
}

bool SE2Manifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<Vector3> out(y_minus_x);
  out = FromAmbient(y).Minus(FromAmbient(x));
  return true;
}

bool SE2Manifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<RowMajorMatrix3> j(jacobian);
  j = BlockRotation(x[2]).transpose();
  return true;
}

}  // namespace groundline::core
