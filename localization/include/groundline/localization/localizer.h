// The causal localizer: the one estimator the service, the dataset replay
// (`groundline localize --dataset`) and the tests drive. It is fed one sensor
// reading at a time, per sensor in time order, and never reads ahead
// (cartographer's TrajectoryBuilderInterface::AddSensorData; basalt's input
// queues):
//   AddWheelReading   wheel encoder increments (the clock of the estimate)
//   AddOdometryIncrement  the same from a planar odometry increment (a
//                     robot that publishes nav_msgs/Odometry, not its wheels)
//   AddFrame          a camera frame, decoded lazily (only when a keyframe
//                     uses it), or AddFloorObservations for lines extracted
//                     elsewhere (the service's camera thread, FloorFrontEnd)
//   AddScan           a planar LiDAR scan
//   SetInitialPose / RequestRelocalization   how the estimate starts
//                     (SetInitialPose again: a re-initialization mid-run)
//
// Pipeline per wheel reading (modes below):
//  1. the reading is checked (finite, stamps increasing; else dropped and
//     counted, never fatal) and integrated (differential drive with
//     covariance, OdometryIntegrator);
//  2. a pending frame whose stamp lies within this reading's interval splits
//     the reading there (the wheel increments scaled by the time fraction,
//     i.e. constant wheel speeds over one reading), so the keyframe sits at
//     the frame's own time; a keyframe is due when the motion since the last
//     one passes KeyframeSelector, or (blind) after blind_keyframe_m without
//     a usable frame;
//  3. scans are matched (lidar/scan_odometry.h) once the odometry covers the
//     time they describe (first-ray stamps moved to mid-sweep);
//  4. a keyframe: the frame's lines (+ with the LiDAR the straight faces of
//     the last scan as wall observations, and the scan-match relative pose)
//     go to the sliding-window smoother on the atlas.
// Between keyframes the pose is the keyframe estimate composed with the
// odometry since (PoseAt, Current).
//
// Modes: kOdometry (dead reckoning), kLines (localization on the atlas:
// floor lines + odometry, optionally the LiDAR), kMapping (the smoother
// builds the atlas), kLidar (LiDAR scan odometry + wheel odometry only).
//
// No ground truth and no simulator: everything arrives through these calls
// and the setup. Not thread-safe: one thread drives it (the service's
// estimator thread).
#ifndef GROUNDLINE_LOCALIZATION_LOCALIZER_H_
#define GROUNDLINE_LOCALIZATION_LOCALIZER_H_

#include <deque>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "groundline/core/dataset.h"
#include "groundline/core/dataset_records.h"
#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/atlas_mapper.h"
#include "groundline/localization/diff_drive_odometry.h"
#include "groundline/localization/floor_front_end.h"
#include "groundline/localization/keyframe_selector.h"
#include "groundline/perception/floor_texture_flow.h"
#include "groundline/localization/lidar/scan_odometry.h"
#include "groundline/localization/lidar/scan_points.h"
#include "groundline/localization/lidar/wall_lines.h"
#include "groundline/localization/relocalizer.h"
#include "groundline/localization/sliding_window_smoother.h"

namespace groundline::localization {
namespace internal {
class LocalizerImpl;
}  // namespace internal

enum class LocalizerMode { kOdometry, kLines, kMapping, kLidar };

struct LocalizerOptions {
  LocalizerMode mode = LocalizerMode::kLines;
  // kLines / kMapping: the LiDAR scan-match factor between keyframes (needs
  // LocalizerSetup::lidar); kLidar always uses the LiDAR.
  bool use_lidar = false;
  // kLines with the LiDAR: the scans' straight faces as line observations
  // against the atlas' wall and rack-face lines.
  bool use_wall_lines = true;
  KeyframeSelector::Options keyframes;
  // The floor's texture tracked from each keyframe's BEV into the next
  // (FloorFlowTracker, into FloorObservations::texture_flow): the motion
  // evidence of the mount's self-calibration in every frame. Off unless the
  // mount is self-calibrated (it costs a few milliseconds per keyframe).
  bool track_floor_texture = false;
  perception::FloorTextureFlowOptions texture_flow;
  // kLines / kMapping: a keyframe without a frame after this much driving,
  // so that the window keeps up with the odometry when the camera is blind.
  double blind_keyframe_m = 1.0;
  // Odometry noise: > 0 models independent wheel errors of this variance per
  // metre of wheel travel with the given lateral variance per metre
  // (OdometryNoiseFromWheelVariance, at the setup's track); 0: `noise`.
  double wheel_variance_m2_per_m = 0.0;
  double lateral_variance_m2_per_m = 1.0e-7;
  OdometryNoiseParams noise;
  // track_m is taken from the setup's drive.
  SmootherOptions smoother;
  lidar::ScanOdometryOptions scan_odometry;
  lidar::ScanPointsOptions scan_points;
  // The scans are deskewed, for the scan matcher and the wall faces alike:
  // each ray is moved to the instant the scan describes by the vehicle's
  // motion over the sweep. A sweeping scanner's rays span 50 ms; undeskewed,
  // a scan taken while the yaw rate ramps (a turn's entry or exit) is bent
  // against a local map built from straight driving, and the match turns it
  // by a bias (docs/localization.md, "Scans from a sweeping scanner").
  // false: every ray from the pose of that instant.
  bool deskew_scans = true;
  // The motion over the sweep is one constant twist: the odometry's mean over
  // this window ending at the scan's instant [s]. Ending there, the scan is
  // matched as soon as the odometry reaches its instant, as undeskewed: a
  // window reaching past it would make the scan wait, and the keyframe after
  // it would compose that much more wheel noise with the match. The mean also
  // smooths the wheels' noise per 10 ms reading, which per-ray interpolation
  // would bend into every scan. Below odometry_history_s.
  double deskew_motion_window_s = 0.1;
  lidar::WallLineOptions walls;
  // kMapping with the LiDAR: the atlas of the whole drive (atlas_mapper.h),
  // read by BuildAtlas.
  AtlasMapperOptions mapper;
  RelocalizerOptions relocalizer;
  // The scan odometry keeps a record per scan (its pose graph) for as long
  // as it runs; after this many scans a fresh one takes over at a keyframe,
  // continuing from the estimate there (one keyframe without a LiDAR
  // relative pose), so that memory stays bounded over a shift: 9000 scans
  // are 10 min at 15 Hz. 0: never.
  int lidar_local_map_scans = 9000;
  // Scans further apart than this (a silent LiDAR) restart the scan odometry
  // (a fresh local map, no relative measurement across the gap) [s].
  double max_scan_gap_s = 1.0;
  // Wheel readings further apart than max_odometry_gap_s: the motion in
  // between is unknown (readings lost or dropped); the next keyframe's
  // odometry covariance grows by this speed and yaw rate over the gap, so
  // that the lines and the LiDAR can pull the pose back.
  double odometry_gap_speed_mps = 2.0;
  double odometry_gap_yaw_rate_radps = 1.0;
  // Exactly zero wheel increments right after a speed above this are frozen
  // encoders, not a stop (dropped and counted until the wheels turn again).
  double frozen_speed_mps = 0.2;
  // A reading in which the difference of the two wheels' speeds (the yaw
  // rate times the track) changes by more than this from the last reading
  // is a wheel that slipped or spun: at 100 Hz, on a 0.76 m track, that is a
  // yaw acceleration of 130 rad/s^2, which no vehicle makes while its wheels
  // hold the floor. The reading is dropped and counted, and the estimate
  // coasts over it on the last good wheel speeds; taken, a 7 cm one-wheel
  // slip turns the heading by 5 deg, and the gates then reject the lines and
  // walls that would correct it. The difference, not each wheel's speed:
  // a reading late or early in transport (its interval miscounted) scales
  // both wheels' speeds alike. Checked between two readings taken in turn,
  // not across a gap or after a coasted reading. 0: off.
  double slip_speed_difference_change_mps = 1.0;
  // Wheel readings with non-finite or frozen increments but a valid stamp:
  // for up to this long the estimate coasts on the last good wheel speeds,
  // its covariance growing as odometry_gap_speed_mps / _yaw_rate_radps times
  // the time since, so that keyframes, the LiDAR and the lines go on (the
  // degraded mode "lines+lidar"); longer outages are a gap [s]. 0: no coasting.
  double max_coast_s = 5.0;
  // Odometry kept for interpolation at scan, ray and query times [s].
  double odometry_history_s = 3.0;
  // Wheel readings further apart than this are counted as a gap (a stalled
  // driver or a clock jump) in the health [s].
  double max_odometry_gap_s = 0.5;
  // A frame more than this behind the newest wheel reading when it arrives
  // is dropped (its time has passed; counted) [s].
  double max_frame_lag_s = 0.5;
  // A sensor is reported stale in the health after this long without data [s].
  double stale_after_s = 1.0;
  // Time. All sensors share one clock (the dataset's and ROS 2's convention).
  // A wheel reading at most this far behind the newest one arrived late (a
  // reordering transport): its increments join the next reading, so that no
  // motion is lost; one at the time of a recent reading is a duplicate
  // (dropped); one further behind is out of order (dropped) [s].
  double reorder_tolerance_s = 0.05;
  // This many consecutive out-of-order readings, each after the one before:
  // the clock jumped back (a time step of the source). The localizer then
  // keeps its own time continuous: every later stamp of every sensor is
  // shifted by the jump on the way in and back on the way out (outputs carry
  // the source's new clock). A forward jump cannot be told from lost
  // readings: it is a gap (max_odometry_gap_s).
  int clock_jump_readings = 10;
  // A scan or frame stamped more than this after the newest wheel reading is
  // dropped (counted): its clock is not the odometry's, e.g. a sensor still
  // on the clock from before a jump [s].
  double max_sensor_lead_s = 2.0;

  core::Status Validate() const;
  // The full system's preset: floor lines + odometry + the LiDAR in the
  // smoother, tuned on the 1.2 km loops of zones A-D (seed 11; docs/localization.md).
  static LocalizerOptions ForFusion();
};

struct LidarSetup {
  core::SE2 T_base_lidar;
  double rate_hz = 15.0;  // one mirror revolution per scan
  core::LidarStamp stamp = core::LidarStamp::kMidSweep;
};

// What the localizer knows about the vehicle and the site.
struct LocalizerSetup {
  DiffDriveParams drive;
  // kLines: the atlas to localize on (floor lines, junctions, wall faces).
  // kMapping starts from an empty atlas; with the LiDAR, this one's
  // landmarks are the site's surveyed ones that tie the built atlas to the
  // site frame (AtlasMapper::SetSurveyedLandmarks), if any.
  Atlas atlas;
  std::optional<LidarSetup> lidar;
  // Needed for AddFrame (kLines / kMapping); AddFloorObservations works without it.
  std::shared_ptr<const FloorFrontEnd> camera;
};

// Counts of everything that was dropped, skipped or failed: the service's
// "never dies, drops and counts".
struct LocalizerCounters {
  long wheel_readings = 0;
  long wheel_dropped_non_finite = 0;
  long wheel_dropped_out_of_order = 0;  // more than reorder_tolerance_s behind the newest
  long wheel_dropped_duplicate = 0;     // the stamp of a reading already taken
  long wheel_late_merged = 0;           // late within reorder_tolerance_s: merged, not lost
  long clock_jumps = 0;                 // the source clock jumped back (clock_jump_readings)
  long wheel_before_start = 0;          // before the start pose was known
  long wheel_dropped_frozen = 0;        // zero increments right after driving (frozen encoders)
  long wheel_dropped_slip = 0;          // a wheel speed step no vehicle makes (a slip, a spin)
  long wheel_coasted = 0;               // dropped readings the estimate coasted over
  long odometry_gaps = 0;               // consecutive readings > max_odometry_gap_s apart
  long frames = 0;
  long frames_used = 0;
  long frames_skipped = 0;        // no keyframe due when the frame's turn came
  long frames_superseded = 0;     // a newer frame arrived before this one's turn
  long frames_unreadable = 0;     // the loader or the front end failed
  long frames_dropped_late = 0;   // max_frame_lag_s behind, or before the start
  long frames_dropped_ahead = 0;  // max_sensor_lead_s ahead of the odometry
  long scans = 0;
  long scans_dropped_bad = 0;
  long scans_dropped_out_of_order = 0;
  long scans_before_start = 0;
  long scans_dropped_ahead = 0;  // max_sensor_lead_s ahead of the odometry
  long scans_matched = 0;
  long keyframes = 0;
  long solve_failures = 0;
  long solves_unconverged = 0;
  long lidar_failures = 0;
  long lidar_restarts = 0;               // the scan odometry restarted after a gap
  long lidar_local_map_renewals = 0;     // a fresh scan odometry after lidar_local_map_scans
  long reinitializations = 0;            // initial poses applied after the start
  long initial_poses_dropped_ahead = 0;  // max_sensor_lead_s ahead of the odometry
  long initial_poses_dropped_late = 0;   // before the odometry history (SetInitialPose)
  long initial_poses_superseded = 0;     // replaced before the odometry reached their stamp
  long lines_used = 0;
  long lines_rejected = 0;
  long lines_dropped = 0;
  long landmarks_born = 0;     // the atlas upkeep (SmootherOptions::upkeep)
  long landmarks_retired = 0;  // the atlas upkeep
  long lidar_keyframes = 0;
  long lidar_degenerate = 0;
  long lidar_fisher_degenerate = 0;
  long lidar_aliased = 0;
  long lidar_with_relative = 0;
  long walls_observed = 0;
  long walls_used = 0;
  long walls_ambiguous = 0;

  // Wheel readings dropped for any reason (the merged late ones are not lost).
  long WheelReadingsDropped() const {
    return wheel_dropped_non_finite + wheel_dropped_out_of_order + wheel_dropped_duplicate +
           wheel_dropped_frozen + wheel_dropped_slip;
  }
};

struct WallCounts {
  int observed = 0;
  int used = 0;  // associated with an atlas face at the prediction
  int ambiguous = 0;
};

// Which sensors have delivered lately (stale_after_s, by the wheel clock).
struct SensorState {
  bool camera_ok = false;
  bool lidar_ok = false;
  double camera_age_s = -1.0;  // since the last frame (-1: none yet)
  double lidar_age_s = -1.0;
  bool odometry_frozen = false;  // the encoders report no motion while driving
  // No frozen or non-finite reading within stale_after_s.
  bool odometry_ok = true;
  // "full" when every configured sensor is ok; else the '+'-joined list of
  // those that are ("lines", "lidar", "odometry"), e.g. "lidar+odometry" with
  // a blind camera, "lines+lidar" with frozen encoders; "none".
  std::string degraded_mode;
};

struct KeyframeOutput {
  long index = 0;  // 0, 1, ... over the run's keyframes
  double stamp_s = 0.0;
  PoseEstimate pose;       // the estimate after the update (kLidar: no covariance)
  PoseEstimate predicted;  // odometry prediction from the previous keyframe
  // The wheel odometry alone at stamp_s (its odom frame, continuous over the
  // run): the motion between keyframes without the lines or the LiDAR, for
  // consumers that must not see the estimate they feed (the self-calibration).
  core::SE2 T_odom_base;
  bool has_covariance = true;
  std::optional<KeyframeHealth> smoother;  // kLines / kMapping
  std::string error;                       // a failed solve or LiDAR stage
  std::optional<double> frame_stamp_s;     // the frame it used
  int lines_dropped = 0;                   // non-SPD covariance
  FloorObservations floor;                 // the frame's observations (no walls)
  std::optional<lidar::ScanOdometryKeyframe> lidar;
  std::optional<WallCounts> walls;
  SensorState sensors;
  double update_cpu_s = 0.0;  // the estimator thread's CPU time for this keyframe
};

class Localizer {
 public:
  // Errors: invalid options; a mode that needs a sensor the setup lacks
  // (the LiDAR), an invalid atlas.
  static core::Result<std::unique_ptr<Localizer>> Create(const LocalizerOptions& options,
                                                         LocalizerSetup setup);
  ~Localizer();

  // Before the start: starts the estimate at stamp_s (readings up to it are
  // not integrated; a relocalization under way is abandoned).
  // After the start: re-initializes the estimate (a lost vehicle put back by
  // hand, RViz's "2D Pose Estimate"), counted as `reinitializations`: the
  // smoother's window restarts with this pose and covariance as its only
  // prior, the wheel odometry goes on (odom frame and path unchanged), and
  // the LiDAR scan odometry is renewed to continue from the new pose (one
  // keyframe without a LiDAR relative pose, as after lidar_local_map_scans),
  // so that nothing pulls the estimate back to the old one. Its time:
  //  - after the newest wheel reading by at most max_sensor_lead_s: held
  //    until the odometry reaches stamp_s and applied there (a later call
  //    replaces a held one: initial_poses_superseded);
  //  - at or before the newest reading, within the odometry history
  //    (odometry_history_s) since the start or the last re-initialization:
  //    applied at the newest reading, carried there by the wheel odometry
  //    since stamp_s (pose and covariance; its noise over the span added).
  // Errors (the pose is dropped and counted, the estimate is unchanged):
  // stamped more than max_sensor_lead_s after the newest wheel reading
  // (initial_poses_dropped_ahead; before the start too, once a reading has
  // arrived: another clock); after the start, stamped before the odometry
  // history (initial_poses_dropped_late); non-finite values, a covariance
  // that is not symmetric positive definite.
  core::Status SetInitialPose(double stamp_s, const core::SE2& T_map_base,
                              const core::Matrix3& covariance);
  // kLines: recognize the start on the atlas from the frames (relocalizer.h);
  // the estimate starts when one hypothesis is unambiguous. Errors: another mode.
  core::Status RequestRelocalization();
  bool started() const;
  // The camera front end rebuilt for another mount (the self-calibrated one,
  // with its covariance, and the mount the observations are expressed under
  // when it is not the BEV's: FloorFrontEnd::WithMount); frames observed
  // from now on use it, and their observations carry the mount. Errors (the
  // front end is unchanged): no camera in the setup; those of WithMount.
  core::Status SetCameraMount(
      const calibration::CameraMount& mount, const Eigen::Matrix4d& covariance,
      const std::optional<calibration::CameraMount>& observed = std::nullopt);
  // Set once a relocalization committed.
  const std::optional<PoseEstimate>& relocalized() const;
  const RelocalizerStatus* relocalizer_status() const;

  // Returns the keyframe this reading closed, if any.
  std::optional<KeyframeOutput> AddWheelReading(const core::WheelEncoderReading& reading);
  // An odometry increment T_prev_curr since the previous reading (identity
  // for the first), taken as the wheel reading that drives its arc
  // (WheelsFromIncrement with the setup's drive; the lateral part is
  // dropped): everything AddWheelReading does and counts applies, and the
  // noise model is the options' (a source's own covariance is not used).
  std::optional<KeyframeOutput> AddOdometryIncrement(double stamp_s, const core::SE2& T_prev_curr);
  // A frame to be decoded when a keyframe uses it; load returns an empty Mat
  // when the frame cannot be read (counted as unreadable).
  using FrameLoader = std::function<cv::Mat()>;
  void AddFrame(double stamp_s, FrameLoader load);
  void AddFloorObservations(ConvertedObservations observations);
  void AddScan(core::LaserScan scan);

  // The pose at the newest wheel reading, with covariance (started() only).
  PoseEstimate Current() const;
  // The pose at stamp_s within the odometry history (interpolated between
  // readings), nullopt outside it or before the start.
  std::optional<PoseEstimate> PoseAt(double stamp_s) const;
  // The odometry since the last keyframe (zero before the start): how far a
  // camera stage is from a frame that a keyframe would use.
  RelativeMotion SinceKeyframe() const;
  // The atlas with the current landmark estimates.
  Atlas CurrentAtlas() const;
  // kMapping with the LiDAR: the atlas of the drive so far, built by the
  // mapper (atlas_mapper.h: the pose graph closed, every landmark solved
  // jointly with the trajectory); report, if given, says what went in.
  // Other modes: CurrentAtlas(). Errors: those of AtlasMapper::Build.
  core::Result<Atlas> BuildAtlas(AtlasMapperReport* report = nullptr);
  // The keyframe trajectory of the last BuildAtlas (empty in other modes);
  // lidar_only: before the joint solve with the landmarks (the odometry
  // corrected by the LiDAR pose graph).
  core::Trajectory MappedTrajectory(bool lidar_only = false) const;
  const LocalizerCounters& counters() const;
  SensorState Sensors() const;
  double path_length_m() const;
  const LocalizerOptions& options() const;

 private:
  explicit Localizer(std::unique_ptr<internal::LocalizerImpl> impl);
  std::unique_ptr<internal::LocalizerImpl> impl_;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_LOCALIZER_H_
