// The Fisher information of a scan match and its degeneracy.
//
// Each point with a surface normal n (scan_points.h) is a point-to-surface
// measurement: its distance along n to the surface is Gaussian with
// point_sigma_m. At the matched pose T (right perturbation xi = (x, y, theta)
// in the base frame) its Jacobian is
//   J_i = n_i^T [I_2, (-p_i.y, p_i.x)^T]   (1x3; n_i and p_i in the base frame)
// and the information is Lambda = s * sum_i J_i^T J_i / point_sigma_m^2, with
// s = min(1, max_independent_points / n): neighbouring points of one scan
// share their errors (the map, the beam model), so more points than that do
// not add information.
//
// Degeneracy: translation and rotation have different units, so the
// eigen-decomposition is done on D Lambda D, D = diag(1, 1, 1 / L), L the RMS
// range of the points (a rotation by 1/L moves a typical point by 1 m). A
// direction whose scaled eigenvalue is below min_eigenvalue_ratio * the
// largest, or below min_eigenvalue (absolute, 1/m^2), is degenerate: in a
// corridor the translation along the aisle. SqrtInformation() keeps only
// the other directions (relative_pose_factor.h), so the scan factor does
// not pull along the aisle.
//
// Pure and thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_MATCH_INFORMATION_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_MATCH_INFORMATION_H_

#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/lidar/scan_points.h"

namespace groundline::localization::lidar {

struct MatchInformationOptions {
  double point_sigma_m = 0.05;
  double max_independent_points = 50.0;
  double min_eigenvalue_ratio = 0.05;
  double min_eigenvalue = 100.0;  // [1/m^2]: a direction known worse than 10 cm

  core::Status Validate() const;
};

struct MatchInformation {
  core::Matrix3 information = core::Matrix3::Zero();       // tangent (x, y, theta) of T_grid_base
  core::Matrix3 sqrt_information = core::Matrix3::Zero();  // S^T S = kept part of information
  // Eigenvalues of the scaled information D Lambda D, ascending [1/m^2], and
  // the unit eigenvector of the smallest one, mapped back to (x, y, theta)
  // (theta in rad) and normalized.
  core::Vector3 scaled_eigenvalues = core::Vector3::Zero();
  core::Vector3 weakest_direction = core::Vector3::Zero();
  int rank = 0;  // number of directions kept
  bool degenerate = false;
  int points_with_normal = 0;
};

// points: the scan (base frame) with normals; only points with a normal count.
MatchInformation ComputeMatchInformation(const std::vector<ScanPoint>& points,
                                         const MatchInformationOptions& options);

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_MATCH_INFORMATION_H_
