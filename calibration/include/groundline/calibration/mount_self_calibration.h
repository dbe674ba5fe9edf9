// Online self-calibration of the floor camera's mount (pitch, roll, height,
// yaw) from the floor lines perception finds while the vehicle drives.
//
// Why it is observable. A wrong mount warps the whole bird's-eye view by one
// floor-to-floor homography (mount_remap.h): a wrong pitch makes lines that
// run ahead converge or diverge and compresses the view along x
// non-linearly, a wrong roll tilts lines across the view unequally and shears
// the view, a wrong height scales it about the camera's ground point, a wrong
// yaw turns it. Three kinds of evidence undo the warp:
//  - structure: markings that are parallel on the floor (the two edges of a
//    lane, tape beside a joint) or perpendicular (a stop bar across a lane)
//    must be so in the view (pitch, roll);
//  - motion: the same marking seen from several places along a straight
//    drive must stay put on the floor once the odometry's motion is undone
//    (pitch and roll through the non-linear warp, height through the scale,
//    yaw through the direction of travel);
//  - known spacings (optional): lines a known distance apart on the floor
//    (a lane's width from the layout) fix the scale, hence the height,
//    independently of the odometry's wheel scale.
//
// Method. Frames are collected into windows of a straight, steady drive (the
// odometry's yaw rate and acceleration below their gates: a turn slides the
// wheels and an acceleration pitches the chassis, so neither is evidence
// about the mount at rest). Each window is one small least-squares problem
// (Ceres): the mount correction, one line landmark per marking tracked
// through the window (in the window's first base frame), and the frames'
// poses tied by the odometry; observation residuals are the distances of each
// observed segment's remapped endpoints from its landmark, whitened by the
// segment's covariance, with a Cauchy loss (clutter, a worn piece of tape);
// structure residuals tie landmarks the view shows nearly parallel or nearly
// perpendicular, with a Cauchy loss (not every such pair is one on the
// floor). The window's information about the mount (the Schur complement of
// its problem, with the weak regularizing prior taken out again) is fused
// into the running estimate, a random walk: the estimate follows a slow
// drift (tire wear) by its process noise. A window whose estimate disagrees
// with the running one beyond chi-square (normalized innovation squared) for
// `step_windows` windows in a row is a step (a payload, a knock): the
// running estimate is restarted from the last of them (the first may
// straddle the step), so it follows a step within a few windows instead of
// averaging it away. A lone window over the gate is dropped (clutter, a
// marking that is not straight).
//
// The alarm (a knocked camera): the estimate differs from the commissioned
// mount by more than a component's threshold, and by 2 sigma more, after two
// window updates in a row (the windows in a row that showed a step count
// among them: each disagreed with the mount from before). The
// thresholds separate a bent bracket (roll, yaw) from the load a vehicle
// carries (pitch, height within a payload's range).
//
// Scale. With no known spacing in view the height is as good as the scale of
// the motion given with the frames: a wheel radius 0.1 % off puts the height
// 0.1 % (0.6 mm) off. Give the localizer's fused motion, or known spacings,
// where the wheels are not trusted to that level.
//
// Thread-safety: not thread-safe; one object per camera, fed in time order.
#ifndef GROUNDLINE_CALIBRATION_MOUNT_SELF_CALIBRATION_H_
#define GROUNDLINE_CALIBRATION_MOUNT_SELF_CALIBRATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

// The estimated components, in this order in every vector and matrix.
enum MountComponent { kMountPitch = 0, kMountRoll = 1, kMountHeight = 2, kMountYaw = 3 };
using MountVector = Eigen::Matrix<double, 4, 1>;  // pitch_rad, roll_rad, height_m, yaw_rad
using MountMatrix = Eigen::Matrix<double, 4, 4>;

// A component for a person: its name ("pitch", ...), its display unit
// ("deg", or "mm" for height) and a value (rad, m) in that unit.
const char* MountComponentName(int component);
const char* MountComponentUnit(int component);
double MountComponentInUnit(int component, double value);

// The estimated components of a mount, and a mount with them replaced
// (forward and lateral kept).
MountVector MountComponents(const CameraMount& mount);
CameraMount WithMountComponents(CameraMount mount, const MountVector& components);

// The atlas line a segment is a sighting of (the vehicle localized on an
// atlas associated it): its id, its line in the map frame, and the line's
// uncertainty where it was seen (across the line, and its direction). Only
// the relative geometry of two atlas lines seen in one window is used (their
// angle, and the distance between parallel ones): it does not depend on
// where the vehicle is, so it cannot confirm a mount that the localized pose
// absorbed.
struct MapLineRef {
  std::int64_t id = 0;
  double rho_m = 0.0;
  double alpha_rad = 0.0;
  double sigma_m = 0.0;
  double sigma_rad = 0.0;
};

// One floor line segment as perception found it, in base_link, under the mount
// its frame's BEV was made with; covariance of its Hesse (rho_m, alpha_rad)
// about the origin of base_link (perception's ExtractedLine::covariance).
struct FloorSegment {
  Eigen::Vector2d start_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d end_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  std::optional<MapLineRef> map_line;  // unset: not associated with an atlas line
};

// The floor's texture tracked from the previous frame into this one
// (perception/floor_texture_flow.h): pairs of floor points in base_link, the
// previous one under the previous frame's mount, the current one under this
// frame's. Under the right mount each pair is one point of the floor seen
// from two poses.
struct FloorFlow {
  double previous_stamp_s = 0.0;  // the frame the points were tracked from
  CameraMount previous_mount;     // its BEV's mount
  // This frame's BEV's mount, when it is not the frame's (MountFrame::
  // mount_used: the frame's lines were re-expressed under a better estimate
  // of the mount than its BEV was made with; the texture is tracked in the
  // BEV itself). Unset: mount_used.
  std::optional<CameraMount> current_mount;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> points;  // (previous, current)
};

// One camera frame's lines and where the vehicle was.
struct MountFrame {
  double stamp_s = 0.0;
  // The odometry's pose at the frame's stamp (any fixed odom frame).
  core::SE2 T_odom_base;
  // The mount the frame's BEV was made with (the segments are under it).
  CameraMount mount_used;
  std::vector<FloorSegment> segments;
  // The texture tracked from the frame before (none: no texture evidence).
  FloorFlow flow;
};

// The defaults are the reference floor camera's (0.58 m high, 42.4 deg):
// set on the synthetic aisle of the tests and the zone B knock scenario
// (seed 7), checked on zone B seed 5 and zone A seed 3
// (docs/2026-12-04-self-calibration.md).
struct MountSelfCalibrationOptions {
  // Windows.
  double window_s = 1.5;             // a window closes after this much time ..
  int min_window_frames = 4;         // .. and is used with at least this many frames
  // .. or after this much while a step is suspected that would raise the
  // alarm (MountEstimate::step_suspected, its mount beyond a component's
  // alarm_threshold from the commissioned one): the windows that confirm or
  // drop it come sooner, so that a knock that came in a turn, where no
  // window is made, is alarmed soon after the drive is straight again. A
  // smaller step (a payload) waits for windows of the usual length: the
  // estimate restarts from the window that confirms it, and a short one
  // restarts it less accurately (zone B seed 14: 1.5 mm of height off
  // after a payload, and 0.3 cm more ATE over the drive). At most window_s.
  double suspected_window_s = 0.6;
  double max_frame_gap_s = 0.6;      // a longer gap closes the window
  double max_yaw_rate_rad_s = 0.05;  // straight-drive gate (about 3 deg/s)
  double max_accel_mps2 = 0.3;       // steady-drive gate
  double min_speed_mps = 0.2;        // standing still shows no motion evidence
  // Segments.
  double min_segment_length_m = 0.3;
  double min_segment_sigma_m = 0.0005;  // floor on each endpoint's distance sigma
  // Association across frames: the landmark predicted into the frame with the
  // odometry and the current estimate, against the segment remapped to it.
  double associate_max_angle_rad = 0.035;
  double associate_max_distance_m = 0.04;
  // A marking counts when tracked through at least this many frames of the
  // window (a single sighting is as likely clutter).
  int min_track_frames = 3;
  // Structure: landmarks whose directions differ by less than this (from
  // parallel, or from perpendicular) are tied with parallel_sigma_rad.
  double structure_gate_rad = 0.05;
  double parallel_sigma_rad = 0.0015;
  bool use_perpendicular = true;
  // Known spacings between parallel lines (m, e.g. a lane's width); a pair of
  // parallel landmarks whose separation is within spacing_gate_m of one is
  // tied to it with spacing_sigma_m. Empty: none.
  std::vector<double> known_spacings_m;
  double spacing_gate_m = 0.03;
  double spacing_sigma_m = 0.002;
  // The atlas's geometry (FloorSegment::map_line): two markings of a window
  // that are sightings of two atlas lines are tied to the atlas's angle
  // between them (parallel_sigma_rad added to the lines' own direction
  // sigmas: paint is not perfectly straight), and two parallel ones to its
  // distance between them (map_spacing_sigma_m added to the lines' own
  // sigmas across them: where the paint's edge is). The pair's generic
  // structure tie is then not added. A distance is scale, so height,
  // independent of the wheels.
  bool use_map_geometry = true;
  double map_spacing_sigma_m = 0.001;
  // Odometry noise of the frames' relative poses: per metre driven (along
  // and across, m/sqrt(m)) and heading (rad/sqrt(m)).
  double odometry_sigma_m_per_sqrt_m = 0.002;
  double odometry_sigma_rad_per_sqrt_m = 0.006;
  // The relative error of the motion's scale (the wheels' radii, 0.1 %):
  // it scales every window's motion alike, and the height from the motion
  // with it, so no number of windows averages it away. The estimate's
  // height variance carries (height * motion_scale_sigma)^2 beside what the
  // windows leave (not fused: every window has the same error). 0: the scale
  // is exact.
  double motion_scale_sigma = 1e-3;
  // The same for the yaw: wheels of unequal radii make the odometry curve
  // where the vehicle drives straight, and a window reads half the heading
  // the odometry turns between two frames as yaw (the floor moved straight
  // back in the view). The reference vehicle, wheels 0.1 % off each, 0.76 m
  // apart, frames 0.28 m apart: 0.26 mrad (0.015 deg). 0: none.
  double motion_heading_sigma_rad = 2.6e-4;
  // The correlation of a marking's errors between the frames of a window:
  // what pulls a line off in one frame (a scuff beside it, its wear, the
  // texture under it) pulls it off in the next, so N sightings are worth
  // N / (1 + rho (N - 1)) independent ones; each observation's covariance is
  // raised by 1 + rho (N - 1). 1: the sightings of a marking count as one
  // (the rendered zone B drives, seeds 5 and 12, put roll 5 sigma off with
  // independent sightings); 0: independent (white noise, the synthetic tests).
  double track_correlation = 1.0;
  // The floor's texture (MountFrame::flow): each pair's two points, moved
  // into the window frame by their frames' poses, must meet. A pair is used
  // when its frame follows the one it was tracked from in the window, and
  // when its points meet within flow_gate_m under the window's starting
  // mount and the odometry (what stands on the floor, glare and the vehicle's
  // shadow do not move with the floor). flow_sigma_m: each point's tracking
  // error per axis on the floor. The errors of one frame pair's points are
  // correlated (the vehicle's vibration moves the whole view, the texture
  // under a window is smooth): N points are worth N / (1 + rho (N - 1))
  // independent ones.
  bool use_floor_flow = true;
  int max_flow_points = 60;    // per frame pair, the rest dropped evenly
  int min_flow_points = 12;    // fewer: the frame pair is not used
  double flow_gate_m = 0.02;
  double flow_sigma_m = 0.001;
  double flow_correlation = 0.02;
  // Cauchy loss scale of the whitened observation and structure residuals.
  double loss_scale = 2.0;
  // The window's regularizing prior about the running estimate (taken out of
  // the window's information again before fusion): wide, only for the
  // directions a window does not see.
  MountVector window_prior_sigma = (MountVector() << 0.05, 0.05, 0.05, 0.05).finished();
  // The commissioned mount's uncertainty: the running estimate's start, and
  // its restart after a step.
  MountVector initial_sigma = (MountVector() << 0.02, 0.02, 0.02, 0.02).finished();
  // A step's plausible size per component: a payload flexes the mast by
  // about a degree and presses the tires by millimetres, a knock turns the
  // bracket by a degree or so. A suspected step is the running estimate
  // widened by it and fused with the evidence that showed the step, so the
  // components the step did not move keep what the estimate knew of them
  // (one frame pair of texture sees the pitch well and the height poorly).
  // A confirmed step restarts from initial_sigma instead, with a window's
  // evidence: a larger knock is then not held back by this.
  MountVector step_sigma = (MountVector() << 0.0175, 0.0087, 0.005, 0.0175).finished();
  // Random walk of the true mount (per sqrt(s) of driving time): lets the
  // estimate follow tire wear and a slowly settling load.
  MountVector random_walk_per_sqrt_s = (MountVector() << 2e-5, 2e-5, 2e-5, 2e-5).finished();
  // Step detection: normalized innovation squared of a window over the
  // chi-square quantile step_probability for step_windows windows in a row.
  double step_probability = 0.9999;
  int step_windows = 2;
  // A step too small for one window (5 mm of height is 4-5 sigma of one
  // window's): the evidence of the last step_evidence_windows windows
  // together, against the estimate from before them, over the same gate is
  // a step too; the estimate restarts from before them with all of them but
  // the first (which may straddle it). Where a frame pair over the gate
  // showed when a step came, the windows since then (at least two, at most
  // step_evidence_windows) are tested so too, as each closes, and a step
  // restarts the estimate from before them with all of them. 0: off.
  int step_evidence_windows = 4;
  // A step suspected before a window closes: the floor's texture of one
  // frame pair (the frame and the one before, solved as a window of two)
  // over the step gate for this many frame pairs in a row. It only marks a
  // suspected step (MountEstimate::step_suspected, so that the localizer
  // reads the lines under the suspected mount at once, within a few frames
  // of a payload or a knock instead of the one or two windows a step takes
  // to show); the estimate waits for the windows. The first pair over the
  // gate already marks a suspicion, at the running estimate widened by a
  // step (step_sigma), until this many pairs move it: that frame may be
  // under another mount, which a pair straddling the step cannot tell.
  // 0: off.
  int quick_step_frames = 2;
  // The alarm: |estimate - commissioned| above these (pitch_rad, roll_rad,
  // height_m, yaw_rad) by more than alarm_sigmas sigma.
  MountVector alarm_threshold =
      (MountVector() << 0.026, 0.0044, 0.015, 0.0087).finished();  // 1.5, 0.25 deg, 15 mm, 0.5 deg
  double alarm_sigmas = 2.0;
  // ... after this many window updates in a row (a lone window can be off).
  // A step's windows count: each of them disagreed with the mount from
  // before, so at a step confirmed by step_windows windows the alarm is
  // raised at once when the restarted estimate meets the condition.
  int alarm_windows = 2;
  int max_solver_iterations = 30;

  core::Status Validate() const;
};

// The running estimate.
struct MountEstimate {
  CameraMount mount;  // the estimated mount itself (forward/lateral as commissioned)
  // Of (pitch, roll, height, yaw); the height and yaw variances include the
  // motion's systematic errors (MountSelfCalibrationOptions::motion_scale_sigma,
  // motion_heading_sigma_rad).
  MountMatrix covariance = MountMatrix::Zero();
  bool alarm = false;
  std::string alarm_message;  // what changed and by how much, when alarm
  // A possible step (a window over the step gate, fewer than step_windows
  // in a row so far, or quick_step_frames frame pairs over it): the mount's
  // components as that evidence shows them, read with the running estimate
  // widened by step_sigma (pitch_rad, roll_rad, height_m, yaw_rad). Until
  // the windows confirm or drop it, the mount may be this far from `mount`.
  bool step_suspected = false;
  MountVector suspected_components = MountVector::Zero();
  // Their covariance: the running estimate widened by a step
  // (MountSelfCalibrationOptions::step_sigma) fused with the evidence that
  // showed it, and the motion's systematic errors.
  MountMatrix suspected_covariance = MountMatrix::Zero();
  // Counters since the start.
  int frames = 0;
  int frames_gated = 0;  // not straight or steady
  int windows_used = 0;
  int windows_rejected = 0;    // too few frames or evidence, or the solve failed
  int steps = 0;               // steps detected
  int windows_with_atlas = 0;  // windows fused with an atlas distance (MapLineRef)
  double last_update_s = 0.0;  // stamp of the last window fused (0: none)
};

// The result of solving one window (exposed for the tests and diagnostics).
struct MountWindowSolution {
  bool ok = false;
  std::string message;                           // why not ok
  MountVector correction = MountVector::Zero();  // to the reference mount, at the solve
  // The window's own information about the correction and its information
  // vector (Lambda c), the regularizing prior taken out again.
  MountMatrix information = MountMatrix::Zero();
  MountVector information_vector = MountVector::Zero();
  int frames = 0;
  int landmarks = 0;
  int observations = 0;
  int structure_pairs = 0;
  int spacing_pairs = 0;
  int map_pairs = 0;     // pairs tied to the atlas's angle ..
  int map_spacings = 0;  // .. and of them, to its distance
  int flow_pairs = 0;   // frame pairs with texture evidence
  int flow_points = 0;  // their points used
  int iterations = 0;
  double final_cost = 0.0;
};

// Whether `flow` was tracked from `previous` (its stamp, to a millisecond).
bool FlowFollows(const FloorFlow& flow, const MountFrame& previous);

// The normalized innovation squared of evidence given in information form
// (information, information vector) against an estimate (mean, covariance),
// in the directions the evidence sees; *dims: how many (0: none, and 0
// returned).
double EvidenceNis(const MountMatrix& information, const MountVector& information_vector,
                   const MountVector& mean, const MountMatrix& covariance, int* dims);

// Solves one window: frames of one straight drive, their segments under
// their mount_used; the correction is to `reference` (pitch, roll, height,
// yaw added), regularized about `prior_correction`.
MountWindowSolution SolveMountWindow(const std::vector<MountFrame>& frames,
                                     const CameraMount& reference,
                                     const MountVector& prior_correction,
                                     const MountSelfCalibrationOptions& options);

class MountSelfCalibrator {
 public:
  // The commissioned mount (valid, asserted) and valid options (asserted).
  MountSelfCalibrator(const CameraMount& commissioned, const MountSelfCalibrationOptions& options);

  // Continues from a saved estimate (a restart, mount_estimate_file.h): its
  // mount, covariance, alarm and counters. The stamps of a new run are not
  // compared with the saved one's (another clock). Errors: the estimate was
  // made against another commissioned mount (recommissioned since: start
  // afresh), an invalid mount or a covariance that is not symmetric
  // positive definite.
  core::Status Restore(const CameraMount& saved_commissioned, const MountEstimate& saved);

  // Feeds one frame, in stamp order (an older stamp is ignored). Returns true
  // when a window was fused and the estimate changed.
  bool AddFrame(const MountFrame& frame);

  const MountEstimate& estimate() const { return estimate_; }
  const CameraMount& commissioned() const { return commissioned_; }

 private:
  bool FrameQualifies(const MountFrame& frame) const;
  bool HasEvidence(const MountFrame& frame) const;
  bool HasFlowFrom(const MountFrame& frame, const MountFrame& previous) const;
  bool CloseWindow();
  // The frame pair (the last frame, `frame`) over the step gate: counts
  // quick_streak_ and marks a suspected step (quick_step_frames).
  void CheckFramePair(const MountFrame& frame);
  void Fuse(const MountWindowSolution& window, double stamp_s);
  void UpdateEstimate();
  // The commissioning's covariance (a start, a restart after a step) and the
  // random walk's over dt_s.
  MountMatrix InitialCovariance() const;
  MountMatrix RandomWalkCovariance(double dt_s) const;
  // Marks a suspected step at the mount `correction` shows (from frame
  // pairs, or from a window over the step gate), or clears it.
  void Suspect(const MountWindowSolution& evidence, bool from_frames);
  void ClearSuspicion();
  // The evidence of recent_windows_[from..] together against the estimate
  // from before recent_windows_[from], over the step gate: a step, and the
  // estimate restarts from before them with recent_windows_[fuse_from..].
  bool StepInRecentWindows(std::size_t from, std::size_t fuse_from, double stamp_s);
  // The index of the first of recent_windows_ that began at or after
  // streak_onset_s_ (their size when none did).
  std::size_t FirstRecentWindowAfterOnset() const;
  // Fuses recent_windows_[from..] again into a restarted estimate (their
  // counts stay those of one fusion).
  void FuseRecentWindowsAgain(std::size_t from);
  // The variances of the motion's systematic errors, added to the
  // estimate's (motion_scale_sigma, motion_heading_sigma_rad).
  MountVector SystematicVariance(double height_m) const;

  CameraMount commissioned_;
  MountSelfCalibrationOptions options_;
  // The running estimate as a correction to the commissioned mount.
  MountVector mean_ = MountVector::Zero();
  MountMatrix covariance_ = MountMatrix::Zero();
  double last_fused_stamp_s_ = -1.0;
  double last_windowed_stamp_s_ = -1e300;  // the last frame of the last window
  int alarm_streak_ = 0;                   // updates in a row with the alarm's condition
  int quick_streak_ = 0;                   // frame pairs in a row over the step gate
  bool quick_suspicion_ = false;           // step_suspected from frame pairs, no window
  // The first frame after the pair that began the last streak of pairs over
  // the step gate: the window open at it is solved from it on, and the
  // windows since it are tested together while onset_pending_.
  double streak_onset_s_ = -1e300;
  bool onset_pending_ = false;
  MountWindowSolution streak_evidence_;  // the pairs of quick_streak_ after its first, summed
  std::vector<MountFrame> window_;
  std::deque<MountFrame> recent_;            // the last frames, for the motion gates
  // A window, with the estimate from before it.
  struct RecentWindow {
    MountWindowSolution window;
    MountVector mean_before;
    MountMatrix covariance_before;
    double stamp_s = 0.0;        // of its last frame
    double first_stamp_s = 0.0;  // of its first frame (after a cut at a streak's onset)
  };
  std::deque<RecentWindow> suspect_;         // windows over the step gate in a row
  std::deque<RecentWindow> recent_windows_;  // the last windows fused
  MountEstimate estimate_;
};

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_MOUNT_SELF_CALIBRATION_H_
