// Scan-to-grid matching: where does a scan fit best in a probability grid?
//
// 1. CorrelativeSearch: an exhaustive search over a bounded window around a
//    predicted pose (Olson 2009, "Real-time correlative scan matching"):
//    every angle step (the angle that moves the farthest point by one cell)
//    and every cell offset; the score is the mean grid probability under the
//    points, times exp(-(w_t |dt|^2 + w_r dtheta^2)) so that ties go to the
//    prediction.
// 2. RefineScanMatch: Ceres least squares of the points against the bicubic
//    interpolation of the grid (ceres::BiCubicInterpolator, as Cartographer's
//    OccupiedSpaceCostFunction2D):
//      r_i = w_occ / sqrt(n) * (1 - P(T_grid_base * p_i))   (Cauchy loss)
//    plus weak regularizers w_t * (t - t_0), w_r * (theta - theta_0) toward
//    the correlative result (pulling toward the odometry prediction instead
//    biased good matches on the real logs; along a featureless aisle the
//    caller replaces the unconstrained component, see lidar_slam.h). Points whose cell at the
//    correlative pose is known free (and no neighbour is occupied: a pallet moved, a person passed)
//    are dropped before the refinement.
// 3. MatchInformation (match_information.h): the Fisher information of the
//    result.
//
// Poses: T_grid_base, the pose of the robot's base in the grid's frame.
// Thread-safety: all functions are pure given a const grid.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_SCAN_MATCHER_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_SCAN_MATCHER_H_

#include <ceres/cubic_interpolation.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/lidar/probability_grid.h"

namespace groundline::localization::lidar {

// Bicubic interpolation of a grid's probabilities; the grid must outlive it
// and not change meanwhile.
class GridInterpolator {
 public:
  explicit GridInterpolator(const ProbabilityGrid& grid);
  // P at point_m (grid frame) and, optionally, dP/dpoint [1/m].
  double Probability(const core::Vector2& point_m, core::Vector2* gradient = nullptr) const;

 private:
  double inverse_resolution_;
  core::Vector2 origin_m_;
  ceres::Grid2D<float, 1> grid_;
  ceres::BiCubicInterpolator<ceres::Grid2D<float, 1>> interpolator_;
};

// One point's residual r = weight * (1 - P(T_grid_base * p)), parameter block
// (x, y, yaw) of T_grid_base (ambient Jacobian).
class GridPointCost final : public ceres::SizedCostFunction<1, 3> {
 public:
  GridPointCost(const GridInterpolator* grid, const core::Vector2& point_base_m, double weight)
      : grid_(grid), point_base_m_(point_base_m), weight_(weight) {}

  // The residual and its Jacobian w.r.t. a right perturbation of T_grid_base.
  double Residual(const core::SE2& T_grid_base, Eigen::Matrix<double, 1, 3>* J_r_T = nullptr) const;
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const GridInterpolator* grid_;
  core::Vector2 point_base_m_;
  double weight_;
};

struct ScanMatcherOptions {
  // Correlative search window around the prediction (half widths).
  double linear_window_m = 0.2;
  double angular_window_rad = 0.35;
  // The angle step is the one that moves the farthest point by one cell, but
  // at least this (the refinement recovers the rest).
  double min_angle_step_rad = 0.005;
  // Points used by the correlative search (every k-th, at most this many).
  int max_search_points = 120;
  double translation_delta_weight = 10.0;  // [1/m^2] in the score's exp()
  double rotation_delta_weight = 2.0;      // [1/rad^2]
  // Refinement.
  double occupied_weight = 1.0;
  double translation_weight = 2.0;  // [1/m]
  double rotation_weight = 4.0;     // [1/rad]
  double cauchy_scale = 0.4;
  double free_probability = 0.35;  // below this a known cell is free space
  int max_iterations = 20;

  core::Status Validate() const;
};

struct ScanMatchResult {
  core::SE2 T_grid_base;
  double correlative_score = 0.0;  // mean probability at the correlative pose, [0, 1]
  double score = 0.0;              // mean probability at the refined pose
  int points_used = 0;
  int points_rejected_free = 0;
  int iterations = 0;
  bool converged = false;
};

// Mean grid probability (nearest cell) under the points at T_grid_base.
double ScoreAt(const ProbabilityGrid& grid, const std::vector<core::Vector2>& points_base_m,
               const core::SE2& T_grid_base);

// The best pose of the window around `prediction` (step 1 above); *score set.
core::SE2 CorrelativeSearch(const ProbabilityGrid& grid,
                            const std::vector<core::Vector2>& points_base_m,
                            const core::SE2& prediction, const ScanMatcherOptions& options,
                            double* score);

// Steps 1 and 2: the correlative search around `prediction` (or, when
// `initial_guess` is given, no search: the refinement starts there), then
// the refinement, regularized toward its starting pose. Errors: no points, every
// point on free space, or the refinement failed numerically.
core::Result<ScanMatchResult> MatchScan(const ProbabilityGrid& grid,
                                        const std::vector<core::Vector2>& points_base_m,
                                        const core::SE2& prediction,
                                        const ScanMatcherOptions& options,
                                        const std::optional<core::SE2>& initial_guess = {});

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_SCAN_MATCHER_H_
