// The LiDAR pose graph (sparse pose adjustment, Konolige et al. 2010, in the
// form of Cartographer's global SLAM): variables are the global poses
// T_map_node of keyframe nodes and T_map_submap of submaps, each (x, y, yaw)
// under core::SE2Manifold; constraints are RelativePoseFactor's:
//   kOdometry:    node i -> node i+1, their relative motion (wheel odometry,
//                 or the LiDAR front end's, lidar_slam.h);
//   kIntraSubmap: submap -> node, the node's pose in a submap it was
//                 inserted into (from local SLAM), weighted by the scan
//                 match's information (rank deficient when degenerate);
//   kLoop:        submap -> node, a loop closure, with a Huber loss.
// The first node is held fixed (the map frame is the local frame of the
// first scan).
//
// Optimize() solves, then checks each loop constraint against the graph, in
// the directions its information constrains (an aliased match's error along
// the aisle is no evidence either way): the one that disagrees with it most,
// by more than loop_max_translation_m or loop_max_rotation_rad, is removed and the graph solved again, for up
// to four rounds (a wrong loop bends the graph, so the others are judged
// again without it).
//
// Not thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_POSE_GRAPH_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_POSE_GRAPH_H_

#include <array>
#include <memory>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::localization::lidar {

struct PoseGraphOptions {
  double loop_huber_scale = 3.0;  // on the whitened residual
  // A loop constraint that disagrees with the solved graph by more than
  // this (translation or rotation of Z^-1 T_submap^-1 T_node) is rejected.
  double loop_max_translation_m = 0.3;
  double loop_max_rotation_rad = 0.05;
  int max_iterations = 30;

  core::Status Validate() const;
};

enum class ConstraintKind { kOdometry, kIntraSubmap, kLoop };

struct PoseGraphConstraint {
  ConstraintKind kind = ConstraintKind::kOdometry;
  int from = 0;  // node (odometry) or submap (intra, loop) index
  int to = 0;    // node index
  core::SE2 T_from_to;
  core::Matrix3 sqrt_information = core::Matrix3::Identity();
  bool rejected = false;  // loop constraints the consistency check removed
};

struct PoseGraphSummary {
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int loops_rejected = 0;
  bool converged = false;
};

class PoseGraph {
 public:
  explicit PoseGraph(const PoseGraphOptions& options);

  // Returns the new index. Initial global estimates.
  int AddNode(const core::SE2& T_map_node);
  int AddSubmap(const core::SE2& T_map_submap);
  void AddConstraint(const PoseGraphConstraint& constraint);

  core::Result<PoseGraphSummary> Optimize();

  core::SE2 node(int i) const;
  core::SE2 submap(int i) const;
  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  int num_submaps() const { return static_cast<int>(submaps_.size()); }
  int num_loops(bool accepted_only = true) const;
  const std::vector<PoseGraphConstraint>& constraints() const { return constraints_; }

 private:
  core::Result<PoseGraphSummary> Solve();

  PoseGraphOptions options_;
  // std::array storage in unique_ptr so Ceres' block pointers stay valid.
  std::vector<std::unique_ptr<std::array<double, 3>>> nodes_;
  std::vector<std::unique_ptr<std::array<double, 3>>> submaps_;
  std::vector<PoseGraphConstraint> constraints_;
};

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_POSE_GRAPH_H_
