// 2D LiDAR + wheel odometry SLAM: local submaps with scan-to-submap matching
// (the "front end") and a pose graph with loop closures (the "back end"),
// after Cartographer (Hess et al. 2016).
//
// Per scan (AddScan, in time order):
//   1. predict T_local_base from the previous scan and the odometry increment
//      T_odom_prev^-1 T_odom_base, and by continuing the last scan interval's
//      motion (logs' odometry is sometimes stale, then jumps); the
//      correlative search runs around both and keeps the better;
//   2. match the scan against the older active submap (scan_matcher.h); the
//      result replaces the prediction when its score reaches min_match_score
//      and it moves the scan no further from the odometry's prediction than
//      max_match_correction_* (or the same correction persists);
//      below that, a wide branch-and-bound search (recovery_search) retries;
//      the Fisher information of the match (match_information.h) says which
//      directions the scan constrains;
//   3. a keyframe (moved keyframe_distance_m or turned keyframe_angle_rad
//      since the last one, or keyframe_time_s passed) is inserted into the
//      active submaps and becomes a pose-graph node with a constraint to the
//      previous node (the front end's motion between them, weighted by the
//      odometry noise and the match information: raw odometry increments
//      would carry the log's stale-then-jumping odometry into the graph) and
//      one constraint per submap it went into (weighted by the match
//      information);
//   4. every loop_search_every_n_nodes-th node is searched (branch and bound,
//      loop_closure.h) in each finished submap whose area contains its
//      current global estimate; a match scoring at least loop_min_score after
//      refinement whose scan also agrees with the submap's free space
//      (loop_verification.h) becomes a loop constraint (checked again in
//      PoseGraph::Optimize), weighted by the scan's match information, less
//      its weakest translation when the scan is aliased along it
//      (loop_check_aliasing);
//   5. the graph is solved every optimize_every_n_nodes nodes when new loop
//      constraints arrived, and in Finish().
// Every scan's global pose is its local pose corrected by the graph:
// T_map_base = C * T_local_base, C = T_map_node * T_local_node^-1 of the last
// keyframe node at or before it, moving toward the next node's C linearly in
// time (interpolate_corrections).
//
// Frames: T_odom_base (the log's odometry), T_local_base (the front end's
// drift-prone frame), T_map_base (the graph's frame; equal to the local frame
// at the first scan).
//
// Not thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_LIDAR_LIDAR_SLAM_H_
#define GROUNDLINE_LOCALIZATION_LIDAR_LIDAR_SLAM_H_

#include <limits>
#include <list>
#include <map>
#include <memory>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/localization/diff_drive_odometry.h"
#include "groundline/localization/lidar/loop_closure.h"
#include "groundline/localization/lidar/loop_verification.h"
#include "groundline/localization/lidar/match_information.h"
#include "groundline/localization/lidar/pose_graph.h"
#include "groundline/localization/lidar/scan_aliasing.h"
#include "groundline/localization/lidar/scan_matcher.h"
#include "groundline/localization/lidar/scan_points.h"
#include "groundline/localization/lidar/submaps.h"

namespace groundline::localization::lidar {

struct LidarSlamOptions {
  // How callers turn ranges into the ScanPoints given to AddScan. The voxel
  // filter keeps a point per half cell (Cartographer's 2D value): at the
  // 5 cm of the cell, a cell's worth of returns became one point and the
  // matcher lost a wall's sub-cell spread (docs/lidar_slam.md).
  ScanPointsOptions points{.voxel_size_m = 0.025};
  ProbabilityGridOptions grid;
  ScanMatcherOptions matcher;
  // Degenerate below 1 % of the largest scaled eigenvalue (the default 5 %
  // discarded the information that corridor scans do carry along the aisle,
  // docs/lidar_slam.md).
  MatchInformationOptions information{0.05, 50.0, 0.01, 100.0};
  BranchAndBoundOptions loop_search;
  PoseGraphOptions graph;
  // Odometry increment noise of a typical indoor research robot, far looser
  // than a calibrated AGV's (diff_drive_odometry.h).
  OdometryNoiseParams odometry_noise{4e-3, 1e-3, 1e-2, 2e-3, 1e-3};
  // The front end's motion between consecutive keyframes is a pose-graph
  // constraint whose information is the odometry's (the noise above plus this
  // floor: logs' odometry is sometimes stale, then jumps) plus the scan
  // match's in the directions it constrains.
  double motion_floor_sigma_m = 0.02;
  double motion_floor_sigma_rad = 0.02;

  int scans_per_submap = 40;  // keyframes
  double keyframe_distance_m = 0.15;
  double keyframe_angle_rad = 0.05;
  double keyframe_time_s = 5.0;
  // A constant-velocity prediction is searched too when it differs from the
  // odometry's by more than this.
  double hypothesis_distance_m = 0.05;
  double hypothesis_angle_rad = 0.035;
  // ... and replaces the odometry's only when its score is higher by this
  // (along a weak aisle the two score alike, and a continued velocity would
  // let the front end slide).
  double hypothesis_min_gain = 0.03;
  // Trajectory(): between keyframes, interpolate the graph's correction
  // (see the top of this file); false: the last node's.
  bool interpolate_corrections = true;
  double min_match_score = 0.3;
  // A match that moves the scan more than this from the odometry's
  // prediction (since the last scan's matched pose) is not used: the
  // prediction is kept. With a calibrated vehicle's wheels the correction
  // per scan is millimetres; a jump of degrees is a scan that does not see
  // the submap (another vehicle or a person right at the sensor). Infinite:
  // no gate (a log's stale-then-jumping odometry needs the matcher's
  // correction, whatever its size).
  double max_match_correction_m = std::numeric_limits<double>::infinity();
  double max_match_correction_rad = std::numeric_limits<double>::infinity();
  // ... unless the scans keep asking for it: a correction beyond the gate
  // that this many consecutive scans repeat (within the gate of each other)
  // is the wheels' error, not the scans' (a slip), and the last of them is
  // used.
  int match_correction_persist_scans = 3;
  // When the match scores below min_match_score (stale or jumping odometry),
  // a branch-and-bound search over this window around the prediction.
  BranchAndBoundOptions recovery_search{1.0, 3.14159265358979, 5, 150};
  double loop_min_score = 0.6;
  // A loop match must also agree with the submap's free space
  // (loop_verification.h) before it enters the graph.
  FreeSpaceCheckOptions loop_free_space;
  // A loop match of a scan that looks the same shifted along its weakest
  // direction (a rack aisle repeating every bay, scan_aliasing.h) constrains
  // only the other directions: in such a place the branch-and-bound finds
  // the best-scoring bay of its window, which a moved pallet or a passing
  // vehicle can make the wrong one, and a constraint a bay off pulls the
  // graph after it. Off by default: a research robot's corridors (the CARMEN
  // logs) were tuned without it; AtlasMapperOptions::DefaultSlam turns it on.
  bool loop_check_aliasing = false;
  ScanAliasingOptions loop_aliasing;
  // A loop match with a runner-up (loop_search.runner_up_distance_m > 0:
  // another pose of the window scoring nearly as well) is ambiguous along
  // the line between them. When that line is within this angle of the
  // scan's weakest translation, the constraint leaves that translation out;
  // otherwise the loop is dropped (which aisle, which heading: unknown).
  double loop_ambiguity_max_angle_rad = 0.35;
  int loop_search_every_n_nodes = 3;
  int optimize_every_n_nodes = 60;
  int precomputed_cache_size = 24;  // submaps whose loop-search grids stay in memory
  // Keep the grids of finished submaps (the loop search matches against
  // them). A front end without loop closures (scan odometry) releases them,
  // so that its memory stays flat over a shift.
  bool retain_finished_submaps = true;

  core::Status Validate() const;
};

struct ScanReport {
  double stamp_s = 0.0;
  core::SE2 T_local_base;
  bool matched = false;              // false: the prediction was kept (first scan, poor match)
  bool velocity_prediction = false;  // the constant-velocity hypothesis won (step 1)
  bool match_gated = false;          // a match beyond max_match_correction_*: not used
  ScanMatchResult match;
  MatchInformation information;
  bool keyframe = false;
  int node = -1;  // pose-graph node of a keyframe
  int loops_found = 0;
  int loops_rejected_free_space = 0;  // matches that contradicted a submap's free space
  bool loop_scan_aliased = false;     // the loop constraints leave out the aliased direction
  int loops_ambiguous = 0;            // constraints that left out a runner-up's direction
  int loops_rejected_ambiguous = 0;   // matches with a runner-up off the weakest direction
};

class LidarSlam {
 public:
  // Asserts that options.Validate() is ok.
  explicit LidarSlam(const LidarSlamOptions& options);

  // Errors: stamps not increasing, or a failed graph solve.
  core::Result<ScanReport> AddScan(double stamp_s, const core::SE2& T_odom_base,
                                   const ScanPoints& scan);
  // Final optimization.
  core::Result<PoseGraphSummary> Finish();

  // T_map_base of every scan added, at its stamp.
  core::Trajectory Trajectory() const;
  const PoseGraph& graph() const { return graph_; }
  int num_submaps() const { return static_cast<int>(submaps_.all().size()); }
  int num_optimizations() const { return num_optimizations_; }

 private:
  struct ScanRecord {
    double stamp_s;
    core::SE2 T_local_base;
    int node;  // last keyframe node at or before the scan
  };
  void AddKeyframe(const core::SE2& T_odom_base, const ScanPoints& scan, ScanReport* report);
  // Adds the verified loop constraints of `node`; counts in *report.
  void SearchLoops(int node, const ScanPoints& scan, ScanReport* report);
  const PrecomputedGrids& Precomputed(const Submap& submap);
  // Odometry increment covariance of a motion, with the floor.
  core::Matrix3 MotionCovariance(const core::SE2& motion) const;

  LidarSlamOptions options_;
  ActiveSubmaps submaps_;
  PoseGraph graph_;
  std::vector<ScanRecord> scans_;
  int gated_streak_ = 0;               // consecutive matches beyond the gate
  core::SE2 gated_correction_;         // the last of them
  std::vector<core::SE2> node_local_;  // T_local_node per node
  std::vector<core::SE2> node_odom_;   // T_odom_node per node
  std::vector<double> node_stamp_s_;
  std::vector<std::vector<int>> node_submaps_;  // submaps a node went into
  core::SE2 last_odom_, last_local_;
  int loops_since_optimization_ = 0;
  int nodes_since_optimization_ = 0;
  int num_optimizations_ = 0;
  std::map<int, std::unique_ptr<PrecomputedGrids>> precomputed_;
  std::list<int> precomputed_lru_;
};

}  // namespace groundline::localization::lidar

#endif  // GROUNDLINE_LOCALIZATION_LIDAR_LIDAR_SLAM_H_
