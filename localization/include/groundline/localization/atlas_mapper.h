// The atlas of a mapping drive with every sensor (mapping mode with the
// LiDAR): floor lines, junctions and the LiDAR's wall and rack faces as
// landmarks of one batch graph over the whole drive, whose trajectory is
// closed by the LiDAR SLAM's submaps and loop closures (lidar_slam.h), after
// Cartographer's split of local and global SLAM.
//
// Fed during the drive (the localizer does it in kMapping with the LiDAR):
//   AddScan      every deskewed scan with the wheel odometry at its instant
//                (LidarSlam: scan-to-submap matching, loop search in the
//                finished submaps, pose-graph solves);
//   AddKeyframe  every keyframe's floor observations and LiDAR faces, in
//                base_link, with the odometry pose there.
// Build() then
//   1. solves the pose graph a last time; every keyframe's pose is its
//      odometry pose corrected by the graph (the correction interpolated
//      between the scans around the keyframe);
//   2. associates the sightings in time order against the landmarks found
//      so far (AssociateLines / AssociateJunctions: Mahalanobis gate, the
//      observed extents overlapping, kinds compatible, ambiguous sightings
//      left out); a floor marking that fits nothing is tried again with the
//      along-track drift (a revisit of a stop bar or a joint after a wheel
//      slip in an aisle); an unmatched sighting starts a landmark; pieces of
//      one line whose extents grew together are merged; landmarks seen in
//      fewer than min_*_sightings keyframes are dropped (a stain, a shadow, a
//      pallet seen once);
//   3. solves keyframe poses and landmarks jointly (Ceres), from the
//      corrected poses: a relative-pose factor between consecutive keyframes
//      (the wheel odometry's motion and covariance, plus a floor; the graph's
//      correction is not a measurement of its own: where it turns abruptly,
//      as over the first scans, it would hold the whole map turned), a
//      GroundLineFactor per line or face sighting and a JunctionFactor per
//      junction sighting (robust loss), the first keyframe held at its
//      pose (the atlas' frame is that of the start pose: anchoring);
//   3b. with surveyed landmarks (SetSurveyedLandmarks: a handful of floor
//      lines, faces or junctions a surveyor measured in the site frame),
//      matches each to the built landmark it must be (near it after the
//      solve, the same kind, extents overlapping, no other line within the
//      gate), adds a prior on that landmark with the survey's covariance and
//      solves again: the built atlas turns and shifts onto the site frame,
//      which one start pose cannot do (a heading error of the wheels over
//      the first metre turns the whole map about its start);
//   4. takes each landmark's covariance from the joint solve's marginal
//      (ceres::Covariance): the uncertainty of the trajectory that saw it is
//      in it, not only the sightings' noise, which would average away with
//      their number while the trajectory's error does not.
// Frames: T_odom_base as the localizer's LiDAR stage holds it (the wheel
// odometry started at the start pose in the map frame), so that the atlas is
// in the map frame of the start pose.
//
// Not thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_ATLAS_MAPPER_H_
#define GROUNDLINE_LOCALIZATION_ATLAS_MAPPER_H_

#include <array>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/diff_drive_odometry.h"
#include "groundline/localization/floor_association.h"
#include "groundline/localization/floor_observation.h"
#include "groundline/localization/lidar/lidar_slam.h"

namespace ceres {
class Problem;
}  // namespace ceres

namespace groundline::localization {

struct AtlasMapperOptions {
  // The LiDAR SLAM (loop closures on): the scan odometry's front end tuned
  // for a calibrated AGV (ScanOdometryOptions::DefaultSlam) with the loop
  // search of lidar_slam.h, whose loops in a place that repeats (a rack
  // aisle's bays, the next aisle) keep no information along the repetition
  // (loop_check_aliasing, loop_search.runner_up_distance_m).
  lidar::LidarSlamOptions slam = DefaultSlam();
  // Sightings against the landmarks so far, at the corrected pose with
  // pose_sigma_* as its uncertainty (how far the graph's trajectory may be
  // from the one that saw a landmark before: the loop closures' residual).
  AssociationOptions association;
  double pose_sigma_m = 0.02;
  double pose_sigma_rad = 0.003;
  // A floor-marking sighting that fits nothing at that accuracy is tried
  // again with this much drift along the direction of travel (in an aisle
  // the LiDAR does not see along it, and a wheel slip stays); it joins a
  // landmark only when exactly one fits. 0: not tried.
  double along_track_sigma_m = 0.3;
  // Landmarks seen in fewer keyframes are dropped. The camera's view is
  // 1.8 m deep and keyframes come every 0.5-1 m at 1-2 m/s with 2 frames/s:
  // a marking crossed once is in two or three keyframes.
  int min_line_sightings = 2;
  int min_face_sightings = 3;
  int min_junction_sightings = 2;
  // Relative-pose factors of the joint solve: the wheel odometry's noise
  // over the keyframe's motion plus this floor.
  OdometryNoiseParams odometry_noise;
  double motion_floor_sigma_m = 0.002;
  double motion_floor_sigma_rad = 0.0005;
  // Robust loss (Huber) on the whitened sighting residual, and on a
  // surveyed landmark's prior.
  double sighting_huber = 2.0;
  // A surveyed landmark is matched to a built one within this distance (at
  // the surveyed line's middle, or between the points) and angle, after the
  // first solve: the map may be turned about its start by milliradians,
  // decimetres at the far end of a zone. Built lines within
  // anchor_same_line_m of the nearest are taken as pieces of the same line;
  // any other within the gate makes the match ambiguous (left out).
  double anchor_gate_m = 0.5;
  double anchor_gate_rad = 0.02;
  double anchor_same_line_m = 0.05;
  int max_iterations = 50;

  core::Status Validate() const;
  static lidar::LidarSlamOptions DefaultSlam();
};

struct AtlasMapperReport {
  int scans = 0;
  int scans_failed = 0;
  int keyframes = 0;
  int loops = 0;           // accepted loop closures
  int loops_rejected = 0;  // removed by the graph's consistency check
  long sightings = 0;      // line, face and junction sightings in the joint solve
  long sightings_ambiguous = 0;
  int lines = 0;  // floor lines in the atlas
  int faces = 0;  // wall and rack faces
  int junctions = 0;
  int landmarks_dropped = 0;  // seen too few times
  double initial_cost = 0.0;
  double final_cost = 0.0;
  bool covariances = false;    // the marginal covariances were computed
  int surveyed = 0;            // surveyed landmarks given (lines, faces, junctions)
  int surveyed_matched = 0;    // tied to a built landmark
  int surveyed_ambiguous = 0;  // more than one built line or junction fitted
};

class AtlasMapper {
 public:
  // Landmarks while they are built (defined in the implementation).
  struct LineTrack;
  struct JunctionTrack;

  // Asserts options.Validate().
  explicit AtlasMapper(const AtlasMapperOptions& options);

  // Where the drive starts in the map frame, with its covariance (the
  // localizer's start pose): the prior that ties the atlas to the site
  // (anchoring). Without it, the first keyframe's corrected pose is held.
  void SetAnchor(const core::SE2& T_map_base, const core::Matrix3& covariance);
  // Surveyed landmarks in the site frame with the survey's covariance
  // (step 3b): a handful of floor lines, faces or junctions far apart, as a
  // floor map of their own (AtlasFromFloorMap) or an atlas file. Without a
  // start pose they alone place the atlas. Errors: an invalid atlas.
  core::Status SetSurveyedLandmarks(Atlas survey);
  // A deskewed scan describing stamp_s, T_odom_base the odometry there.
  // Errors: stamps not increasing (the scan is left out).
  core::Status AddScan(double stamp_s, const core::SE2& T_odom_base, const lidar::ScanPoints& scan);
  // A keyframe's observations (floor lines and junctions; faces: the LiDAR's
  // wall and rack faces), all in base_link at stamp_s, where the odometry is
  // T_odom_base. Keyframes in time order.
  void AddKeyframe(double stamp_s, const core::SE2& T_odom_base, const FloorObservations& floor,
                   const std::vector<LineObservation>& faces);

  // The atlas of everything added so far (steps 1-4 above). Errors: no
  // keyframe, a failed pose-graph or joint solve.
  core::Result<Atlas> Build(AtlasMapperReport* report = nullptr);
  // The keyframes' poses of the last Build (map frame): after the joint
  // solve, and before it (the odometry corrected by the LiDAR pose graph).
  const core::Trajectory& keyframe_trajectory() const { return keyframe_trajectory_; }
  const core::Trajectory& lidar_trajectory() const { return lidar_trajectory_; }

 private:
  struct Keyframe {
    double stamp_s;
    core::SE2 T_odom_base;
    std::vector<LineObservation> lines;  // floor lines, then faces
    std::vector<JunctionObservation> junctions;
  };
  // Step 2: the sightings grouped into landmarks at the poses given.
  void Associate(const std::vector<std::array<double, 3>>& poses,
                 std::vector<LineTrack>* line_tracks, std::vector<JunctionTrack>* junction_tracks,
                 AtlasMapperReport* report) const;
  // Step 3: poses and landmarks solved jointly (the landmarks' parameters
  // written to *line_params / *junction_params, track for track); the
  // problem is returned for the covariances.
  core::Result<std::unique_ptr<ceres::Problem>> SolveJointly(
      const std::vector<LineTrack>& line_tracks, const std::vector<JunctionTrack>& junction_tracks,
      std::vector<std::array<double, 3>>* poses, std::vector<std::array<double, 2>>* line_params,
      std::vector<std::array<double, 2>>* junction_params, AtlasMapperReport* report) const;

  bool HasSurvey() const { return !survey_.lines.empty() || !survey_.junctions.empty(); }
  // Step 3b on the solved problem: priors on the built landmarks that
  // match a surveyed one, then the solve again. site_origin: a constant
  // identity pose block (the survey's frame) that outlives the problem.
  core::Status AnchorToSurvey(const std::vector<LineTrack>& line_tracks,
                              std::vector<std::array<double, 2>>* line_params,
                              std::vector<std::array<double, 2>>* junction_params,
                              double* site_origin, ceres::Problem* problem,
                              AtlasMapperReport* report) const;

  AtlasMapperOptions options_;
  Atlas survey_;
  lidar::LidarSlam slam_;
  core::Trajectory scan_odometry_;  // T_odom_base at each scan the SLAM took
  int scans_failed_ = 0;
  std::vector<Keyframe> keyframes_;
  std::optional<std::pair<core::SE2, core::Matrix3>> anchor_;
  core::Trajectory keyframe_trajectory_, lidar_trajectory_;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_ATLAS_MAPPER_H_
