#include "groundline/localization/lidar/scan_matcher.h"

#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <algorithm>
#include <cmath>

namespace groundline::localization::lidar {
namespace {

// Pulls (x, y, yaw) toward a fixed pose: w_t * (t - t0), w_r * wrap(yaw - yaw0).
class PriorCost final : public ceres::SizedCostFunction<3, 3> {
 public:
  PriorCost(const core::SE2& prior, double translation_weight, double rotation_weight)
      : prior_(prior), w_t_(translation_weight), w_r_(rotation_weight) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* x = parameters[0];
    residuals[0] = w_t_ * (x[0] - prior_.x());
    residuals[1] = w_t_ * (x[1] - prior_.y());
    residuals[2] = w_r_ * core::WrapAngle(x[2] - prior_.yaw());
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobians[0]);
      J.setZero();
      J(0, 0) = w_t_;
      J(1, 1) = w_t_;
      J(2, 2) = w_r_;
    }
    return true;
  }

 private:
  core::SE2 prior_;
  double w_t_, w_r_;
};

double CellProbability(const ProbabilityGrid& grid, int x, int y) {
  return grid.Probability({x, y});
}

}  // namespace

GridInterpolator::GridInterpolator(const ProbabilityGrid& grid)
    : inverse_resolution_(1.0 / grid.resolution_m()),
      origin_m_(grid.origin_m()),
      reader_{&grid},
      interpolator_(reader_) {}

double GridInterpolator::Probability(const core::Vector2& point_m, core::Vector2* gradient) const {
  // Cell centres sit at origin + (i + 0.5) * resolution.
  const core::Vector2 c = (point_m - origin_m_) * inverse_resolution_ - core::Vector2(0.5, 0.5);
  double p = 0.0, dp_drow = 0.0, dp_dcol = 0.0;
  interpolator_.Evaluate(c.y(), c.x(), &p, &dp_drow, &dp_dcol);
  if (gradient != nullptr) *gradient = core::Vector2(dp_dcol, dp_drow) * inverse_resolution_;
  return p;
}

double GridPointCost::Residual(const core::SE2& T_grid_base,
                               Eigen::Matrix<double, 1, 3>* J_r_T) const {
  core::Matrix23 J_q_T;
  const core::Vector2 q = T_grid_base.Act(point_base_m_, J_r_T ? &J_q_T : nullptr);
  core::Vector2 gradient;
  const double p = grid_->Probability(q, J_r_T ? &gradient : nullptr);
  if (J_r_T != nullptr) *J_r_T = -weight_ * gradient.transpose() * J_q_T;
  return weight_ * (1.0 - p);
}

bool GridPointCost::Evaluate(double const* const* parameters, double* residuals,
                             double** jacobians) const {
  const double* x = parameters[0];
  const double c = std::cos(x[2]), s = std::sin(x[2]);
  const core::Vector2& p = point_base_m_;
  const core::Vector2 q(c * p.x() - s * p.y() + x[0], s * p.x() + c * p.y() + x[1]);
  core::Vector2 gradient;
  residuals[0] = weight_ * (1.0 - grid_->Probability(q, &gradient));
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    // Ambient Jacobian: dq/d(x, y, yaw) = [1 0 -s px - c py; 0 1 c px - s py].
    const double dq_dyaw_x = -s * p.x() - c * p.y(), dq_dyaw_y = c * p.x() - s * p.y();
    jacobians[0][0] = -weight_ * gradient.x();
    jacobians[0][1] = -weight_ * gradient.y();
    jacobians[0][2] = -weight_ * (gradient.x() * dq_dyaw_x + gradient.y() * dq_dyaw_y);
  }
  return true;
}

core::Status ScanMatcherOptions::Validate() const {
  if (!(linear_window_m >= 0.0 && angular_window_rad >= 0.0)) {
    return core::Status::Error("search windows must be >= 0");
  }
  if (!(min_angle_step_rad > 0.0)) return core::Status::Error("min_angle_step_rad must be > 0");
  if (max_search_points < 1 || max_iterations < 1) {
    return core::Status::Error("max_search_points and max_iterations must be >= 1");
  }
  if (!(occupied_weight > 0.0 && translation_weight >= 0.0 && rotation_weight >= 0.0 &&
        cauchy_scale > 0.0 && translation_delta_weight >= 0.0 && rotation_delta_weight >= 0.0)) {
    return core::Status::Error("weights must be >= 0 (occupied_weight, cauchy_scale > 0)");
  }
  if (!(free_probability > 0.0 && free_probability < 0.5)) {
    return core::Status::Error("free_probability must be in (0, 0.5)");
  }
  return core::Status::Ok();
}

double ScoreAt(const ProbabilityGrid& grid, const std::vector<core::Vector2>& points_base_m,
               const core::SE2& T_grid_base) {
  if (points_base_m.empty()) return 0.0;
  double sum = 0.0;
  for (const core::Vector2& p : points_base_m) {
    const CellIndex c = grid.CellOf(T_grid_base * p);
    sum += CellProbability(grid, c.x, c.y);
  }
  return sum / static_cast<double>(points_base_m.size());
}

core::SE2 CorrelativeSearch(const ProbabilityGrid& grid,
                            const std::vector<core::Vector2>& points_base_m,
                            const core::SE2& prediction, const ScanMatcherOptions& options,
                            double* score) {
  std::vector<core::Vector2> points;
  const std::size_t stride =
      std::max<std::size_t>(1, points_base_m.size() / options.max_search_points +
                                   (points_base_m.size() % options.max_search_points ? 1 : 0));
  double max_range = 0.0;
  for (std::size_t i = 0; i < points_base_m.size(); i += stride) {
    points.push_back(points_base_m[i]);
    max_range = std::max(max_range, points_base_m[i].norm());
  }
  const double res = grid.resolution_m();
  const double angle_step =
      std::max(options.min_angle_step_rad,
               max_range > res ? std::acos(1.0 - res * res / (2.0 * max_range * max_range)) : 0.1);
  const int n_angles = static_cast<int>(std::ceil(options.angular_window_rad / angle_step));
  const int n_cells = static_cast<int>(std::ceil(options.linear_window_m / res));
  const int side = 2 * n_cells + 1;
  double best = -1.0;
  core::SE2 best_pose = prediction;
  // Sums of the probabilities under the points for every offset: point by
  // point over the rows of the window (contiguous, vectorizable) where the
  // window lies inside an uncompressed grid.
  std::vector<float> sums(static_cast<std::size_t>(side * side));
  std::vector<double> translation_prior(sums.size());
  for (int dy = -n_cells, k = 0; dy <= n_cells; ++dy) {
    for (int dx = -n_cells; dx <= n_cells; ++dx, ++k) {
      translation_prior[k] =
          std::exp(-options.translation_delta_weight * (dx * dx + dy * dy) * res * res);
    }
  }
  const float* raw = grid.compressed() ? nullptr : grid.probabilities().data();
  const int width = grid.width(), height = grid.height();
  std::vector<CellIndex> cells(points.size());
  for (int a = -n_angles; a <= n_angles; ++a) {
    const double dyaw = a * angle_step;
    const core::SE2 rotated(prediction.translation(), prediction.yaw() + dyaw);
    for (std::size_t i = 0; i < points.size(); ++i) cells[i] = grid.CellOf(rotated * points[i]);
    std::fill(sums.begin(), sums.end(), 0.0f);
    for (const CellIndex& c : cells) {
      const bool inside = raw != nullptr && c.x - n_cells >= 0 && c.y - n_cells >= 0 &&
                          c.x + n_cells < width && c.y + n_cells < height;
      for (int dy = -n_cells; dy <= n_cells; ++dy) {
        float* row_sums = &sums[static_cast<std::size_t>((dy + n_cells) * side)];
        if (inside) {
          const float* row = raw + static_cast<std::size_t>(c.y + dy) * width + (c.x - n_cells);
          for (int k = 0; k < side; ++k) row_sums[k] += row[k];
        } else {
          for (int k = 0; k < side; ++k) {
            row_sums[k] += static_cast<float>(CellProbability(grid, c.x - n_cells + k, c.y + dy));
          }
        }
      }
    }
    const double rotation_prior =
        std::exp(-options.rotation_delta_weight * dyaw * dyaw) / static_cast<double>(points.size());
    for (int dy = -n_cells, k = 0; dy <= n_cells; ++dy) {
      for (int dx = -n_cells; dx <= n_cells; ++dx, ++k) {
        const double s = sums[k] * translation_prior[k] * rotation_prior;
        if (s > best) {
          best = s;
          best_pose = core::SE2(prediction.translation() + core::Vector2(dx, dy) * res,
                                prediction.yaw() + dyaw);
        }
      }
    }
  }
  if (score != nullptr) *score = ScoreAt(grid, points, best_pose);
  return best_pose;
}

core::Result<ScanMatchResult> MatchScan(const ProbabilityGrid& grid,
                                        const std::vector<core::Vector2>& points_base_m,
                                        const core::SE2& prediction,
                                        const ScanMatcherOptions& options,
                                        const std::optional<core::SE2>& initial_guess) {
  if (points_base_m.empty()) return core::Status::Error("scan match: the scan has no points");
  ScanMatchResult result;
  core::SE2 initial;
  if (initial_guess) {
    initial = *initial_guess;
    result.correlative_score = ScoreAt(grid, points_base_m, initial);
  } else {
    initial =
        CorrelativeSearch(grid, points_base_m, prediction, options, &result.correlative_score);
  }
  // Points on known free space (nothing occupied within one cell) are
  // objects that were not there when the grid was built.
  std::vector<core::Vector2> kept;
  kept.reserve(points_base_m.size());
  for (const core::Vector2& p : points_base_m) {
    if (grid.IsFreeAround(grid.CellOf(initial * p), options.free_probability)) {
      ++result.points_rejected_free;
    } else {
      kept.push_back(p);
    }
  }
  if (kept.empty()) return core::Status::Error("scan match: every point lies on free space");
  const GridInterpolator interpolator(grid);
  double pose[3] = {initial.x(), initial.y(), initial.yaw()};
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::CauchyLoss loss(options.cauchy_scale / std::sqrt(static_cast<double>(kept.size())));
  const double weight = options.occupied_weight / std::sqrt(static_cast<double>(kept.size()));
  for (const core::Vector2& p : kept) {
    problem.AddResidualBlock(new GridPointCost(&interpolator, p, weight), &loss, pose);
  }
  problem.AddResidualBlock(
      new PriorCost(initial, options.translation_weight, options.rotation_weight), nullptr, pose);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (!std::isfinite(summary.final_cost)) {
    return core::Status::Error("scan match: the refinement diverged (" + summary.message + ")");
  }
  result.T_grid_base = core::SE2(pose[0], pose[1], pose[2]);
  result.score = ScoreAt(grid, kept, result.T_grid_base);
  result.points_used = static_cast<int>(kept.size());
  result.iterations = static_cast<int>(summary.iterations.size());
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  return result;
}

}  // namespace groundline::localization::lidar
