// Line intersections with covariance (junctions.h).
#include "groundline/perception/junctions.h"

#include <Eigen/LU>
#include <cmath>
#include <numbers>

namespace groundline::perception {

core::Status JunctionOptions::Validate() const {
  if (!(min_angle_deg > 0.0 && min_angle_deg <= 90.0)) {
    return core::Status::Error("JunctionOptions.min_angle_deg: expected a number in (0, 90]");
  }
  if (!(reach_tolerance_m >= 0.0) || !std::isfinite(reach_tolerance_m)) {
    return core::Status::Error("JunctionOptions.reach_tolerance_m: expected a number >= 0");
  }
  return core::Status::Ok();
}

const char* JunctionShapeName(JunctionShape shape) {
  switch (shape) {
    case JunctionShape::kL:
      return "L";
    case JunctionShape::kT:
      return "T";
    case JunctionShape::kX:
      return "X";
  }
  return "X";
}

core::Result<Eigen::Vector2d> IntersectLines(const HesseLine& l1, const HesseLine& l2,
                                             Eigen::Matrix2d* J_p_l1, Eigen::Matrix2d* J_p_l2) {
  Eigen::Matrix2d N;
  N.row(0) = l1.Normal().transpose();
  N.row(1) = l2.Normal().transpose();
  const double det = N.determinant();
  if (!(std::abs(det) > 1e-9)) return core::Status::Error("IntersectLines: the lines are parallel");
  const Eigen::Matrix2d N_inv = N.inverse();
  const Eigen::Vector2d p = N_inv * Eigen::Vector2d(l1.rho_m, l2.rho_m);
  // d(N p) = d(rho): dp = N^-1 (e_k d rho_k - e_k (dn_k/d alpha_k . p) d alpha_k).
  if (J_p_l1 != nullptr) {
    J_p_l1->col(0) = N_inv.col(0);
    J_p_l1->col(1) = -N_inv.col(0) * l1.Direction().dot(p);
  }
  if (J_p_l2 != nullptr) {
    J_p_l2->col(0) = N_inv.col(1);
    J_p_l2->col(1) = -N_inv.col(1) * l2.Direction().dot(p);
  }
  return p;
}

namespace {

// How far beyond the segment's ends the point lies (<= 0 inside), and
// whether the point is within tolerance of an end.
struct Reach {
  double outside_m = 0.0;
  bool at_end = false;
};

Reach ReachOf(const LineSegmentEstimate& s, const Eigen::Vector2d& p, double tolerance_m) {
  const Eigen::Vector2d d = s.line.Direction();
  double a = d.dot(s.start_m), b = d.dot(s.end_m);
  if (a > b) std::swap(a, b);
  const double t = d.dot(p);
  Reach r;
  r.outside_m = std::max(a - t, t - b);
  r.at_end = std::min(std::abs(t - a), std::abs(t - b)) <= tolerance_m;
  return r;
}

}  // namespace

std::vector<Junction> FindJunctions(std::span<const LineSegmentEstimate> lines,
                                    const JunctionOptions& options) {
  std::vector<Junction> junctions;
  const double max_cos = std::cos(options.min_angle_deg * std::numbers::pi / 180.0);
  for (size_t i = 0; i < lines.size(); ++i) {
    for (size_t j = i + 1; j < lines.size(); ++j) {
      if (std::abs(lines[i].line.Normal().dot(lines[j].line.Normal())) > max_cos) continue;
      Eigen::Matrix2d J1, J2;
      core::Result<Eigen::Vector2d> p = IntersectLines(lines[i].line, lines[j].line, &J1, &J2);
      if (!p.ok()) continue;
      const Reach ri = ReachOf(lines[i], *p, options.reach_tolerance_m);
      const Reach rj = ReachOf(lines[j], *p, options.reach_tolerance_m);
      if (ri.outside_m > options.reach_tolerance_m || rj.outside_m > options.reach_tolerance_m) {
        continue;
      }
      Junction junction;
      junction.point_m = *p;
      junction.covariance =
          J1 * lines[i].covariance * J1.transpose() + J2 * lines[j].covariance * J2.transpose();
      junction.line_a = static_cast<int>(i);
      junction.line_b = static_cast<int>(j);
      junction.shape = ri.at_end && rj.at_end   ? JunctionShape::kL
                       : ri.at_end || rj.at_end ? JunctionShape::kT
                                                : JunctionShape::kX;
      junctions.push_back(junction);
    }
  }
  return junctions;
}

}  // namespace groundline::perception
