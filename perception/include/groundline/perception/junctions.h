// Junctions: where two roughly perpendicular floor lines meet (a stop bar on
// an aisle tape, a staging-box corner, crossing joints). The point is the
// intersection of the two Hesse lines,
//
//   [n1^T; n2^T] p = [rho1; rho2],   n_k = (cos alpha_k, sin alpha_k),
//
// and its covariance is J1 C1 J1^T + J2 C2 J2^T (the lines are measured
// independently), with J_k = dp/d(rho_k, alpha_k) = N^-1 e_k [1, -d_k . p],
// d_k = (-sin alpha_k, cos alpha_k) the direction of line k, N = [n1^T; n2^T].
// A junction is only reported where both measured segments actually reach the
// point within reach_tolerance_m (an extrapolated crossing is no junction).
// Pure and thread-safe.
#ifndef GROUNDLINE_PERCEPTION_JUNCTIONS_H_
#define GROUNDLINE_PERCEPTION_JUNCTIONS_H_

#include <Eigen/Core>
#include <span>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::perception {

// The intersection of two lines (metres). Fails when the lines are parallel
// within 1e-9 (|det N|). J_p_l1, J_p_l2: d(p)/d(rho, alpha) of each line, 2x2.
core::Result<Eigen::Vector2d> IntersectLines(const HesseLine& l1, const HesseLine& l2,
                                             Eigen::Matrix2d* J_p_l1 = nullptr,
                                             Eigen::Matrix2d* J_p_l2 = nullptr);

// A measured line segment: its line, covariance and the endpoints (on the line).
struct LineSegmentEstimate {
  HesseLine line;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  Eigen::Vector2d start_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d end_m = Eigen::Vector2d::Zero();
};

struct JunctionOptions {
  double min_angle_deg = 70.0;      // the lines must cross at 70..90 deg
  double reach_tolerance_m = 0.10;  // each segment reaches the point within this

  core::Status Validate() const;
};

// L: both segments end at the point; T: one ends there, the other passes
// through; X: both pass through.
enum class JunctionShape { kL, kT, kX };
const char* JunctionShapeName(JunctionShape shape);

struct Junction {
  Eigen::Vector2d point_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  // m^2
  int line_a = 0;  // indices into the input lines, line_a < line_b
  int line_b = 0;
  JunctionShape shape = JunctionShape::kX;
};

// Every qualifying pair, ordered by (line_a, line_b).
std::vector<Junction> FindJunctions(std::span<const LineSegmentEstimate> lines,
                                    const JunctionOptions& options);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_JUNCTIONS_H_
