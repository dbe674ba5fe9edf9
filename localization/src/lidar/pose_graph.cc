#include "groundline/localization/lidar/pose_graph.h"

#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/SVD>

#include <cassert>
#include <cmath>

#include "groundline/core/se2_manifold.h"
#include "groundline/localization/relative_pose_factor.h"

namespace groundline::localization::lidar {
namespace {

std::unique_ptr<std::array<double, 3>> Block(const core::SE2& T) {
  return std::make_unique<std::array<double, 3>>(std::array<double, 3>{T.x(), T.y(), T.yaw()});
}

constexpr int kMaxRejectionRounds = 4;

// The part of a loop's error (tangent, node frame) in the directions its
// information constrains: an aliased or degenerate match says nothing along
// its null directions, so its error there is no sign that it is wrong.
core::Vector3 ConstrainedError(const core::SE2& E, const core::Matrix3& sqrt_information) {
  const core::Vector3 e = E.Log();
  const Eigen::JacobiSVD<core::Matrix3> svd(sqrt_information, Eigen::ComputeFullV);
  const double largest = svd.singularValues()(0);
  core::Vector3 kept = core::Vector3::Zero();
  for (int i = 0; i < 3; ++i) {
    if (svd.singularValues()(i) > 1e-9 * largest) {
      const core::Vector3 v = svd.matrixV().col(i);
      kept += v * v.dot(e);
    }
  }
  return kept;
}

}  // namespace

core::Status PoseGraphOptions::Validate() const {
  if (!(loop_huber_scale > 0.0 && loop_max_translation_m > 0.0 && loop_max_rotation_rad > 0.0)) {
    return core::Status::Error("loop_huber_scale and the loop_max_* must be > 0");
  }
  if (max_iterations < 1) return core::Status::Error("max_iterations must be >= 1");
  return core::Status::Ok();
}

PoseGraph::PoseGraph(const PoseGraphOptions& options) : options_(options) {
  assert(options.Validate().ok());
}

int PoseGraph::AddNode(const core::SE2& T_map_node) {
  nodes_.push_back(Block(T_map_node));
  return num_nodes() - 1;
}

int PoseGraph::AddSubmap(const core::SE2& T_map_submap) {
  submaps_.push_back(Block(T_map_submap));
  return num_submaps() - 1;
}

void PoseGraph::AddConstraint(const PoseGraphConstraint& constraint) {
  assert(constraint.to >= 0 && constraint.to < num_nodes());
  assert(constraint.from >= 0 &&
         constraint.from <
             (constraint.kind == ConstraintKind::kOdometry ? num_nodes() : num_submaps()));
  constraints_.push_back(constraint);
}

core::SE2 PoseGraph::node(int i) const {
  return core::PoseFromAmbient(*nodes_.at(static_cast<std::size_t>(i)));
}

core::SE2 PoseGraph::submap(int i) const {
  return core::PoseFromAmbient(*submaps_.at(static_cast<std::size_t>(i)));
}

int PoseGraph::num_loops(bool accepted_only) const {
  int n = 0;
  for (const PoseGraphConstraint& c : constraints_) {
    n += c.kind == ConstraintKind::kLoop && !(accepted_only && c.rejected);
  }
  return n;
}

core::Result<PoseGraphSummary> PoseGraph::Solve() {
  if (nodes_.empty()) return PoseGraphSummary{};
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  core::SE2Manifold manifold;
  ceres::HuberLoss huber(options_.loop_huber_scale);
  for (const PoseGraphConstraint& c : constraints_) {
    if (c.rejected) continue;
    double* from =
        c.kind == ConstraintKind::kOdometry ? nodes_[c.from]->data() : submaps_[c.from]->data();
    problem.AddResidualBlock(new RelativePoseFactor(c.T_from_to, c.sqrt_information),
                             c.kind == ConstraintKind::kLoop ? &huber : nullptr, from,
                             nodes_[c.to]->data());
  }
  for (auto* blocks : {&nodes_, &submaps_}) {
    for (auto& b : *blocks) {
      if (problem.HasParameterBlock(b->data())) problem.SetManifold(b->data(), &manifold);
    }
  }
  if (problem.HasParameterBlock(nodes_[0]->data())) {
    problem.SetParameterBlockConstant(nodes_[0]->data());
  }
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options_.max_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (summary.termination_type == ceres::FAILURE) {
    return core::Status::Error("pose graph: the solver failed: " + summary.message);
  }
  PoseGraphSummary out;
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  return out;
}

core::Result<PoseGraphSummary> PoseGraph::Optimize() {
  core::Result<PoseGraphSummary> solved = Solve();
  if (!solved.ok()) return solved;
  const double initial_cost = solved->initial_cost;
  int rejected = 0;
  // Reject the loop that disagrees most, solve again; a few rounds at most
  // (a wrong loop bends the graph, so the others are judged after it goes).
  for (int round = 0; round < kMaxRejectionRounds; ++round) {
    PoseGraphConstraint* worst = nullptr;
    double worst_excess = 1.0;
    for (PoseGraphConstraint& c : constraints_) {
      if (c.kind != ConstraintKind::kLoop || c.rejected) continue;
      const core::SE2 E = c.T_from_to.Between(submap(c.from).Between(node(c.to)));
      const core::Vector3 e = ConstrainedError(E, c.sqrt_information);
      const double excess = std::max(e.head<2>().norm() / options_.loop_max_translation_m,
                                     std::abs(e(2)) / options_.loop_max_rotation_rad);
      if (excess > worst_excess) worst_excess = excess, worst = &c;
    }
    if (worst == nullptr) break;
    worst->rejected = true;
    ++rejected;
    solved = Solve();
    if (!solved.ok()) return solved;
  }
  solved->loops_rejected = rejected;
  solved->initial_cost = initial_cost;
  return solved;
}

}  // namespace groundline::localization::lidar
