// Sliding-window SE(2) smoother over keyframes: odometry between-factors,
// ground-line and junction factors against the atlas, and a marginal prior
// that summarizes every keyframe that left the window.
//
// Each keyframe (chosen by the caller, e.g. KeyframeSelector: 0.20 m / 5 deg)
// is a pose block T_map_base (core::SE2Manifold). AddKeyframe:
//  1. predicts the pose from the previous keyframe and the odometry motion
//     (PropagateFromKeyframe), with covariance;
//  2. associates the observations with the atlas (floor_association.h);
//     in mapping mode unmatched ones feed the LandmarkTracker and become
//     landmarks after tracker.min_keyframes sightings; in localization mode
//     with upkeep (AtlasUpkeepOptions) new markings are born the same way
//     and landmarks expected in view and not seen are retired;
//  3. solves the window (pseudo-Huber = ceres::SoftLOneLoss on line and
//     junction factors, scales in whitened units, by iteratively reweighted
//     least squares). Localization mode (landmarks fixed, the window is a
//     chain): Gauss-Newton warm-started from the previous solution, each step
//     solved exactly in O(window) by block elimination (pose_chain_solver.h),
//     Newton's model of the loss until a step raises the cost (an outlier
//     far in the loss's tail), then the reweighted one (Ceres' model, whose
//     steps descend; one that does not is halved), stopping when the largest
//     step component is below step_tolerance or after max_iterations (then
//     on the last poses that did not raise the cost);
//     SmootherSolver::kCeres solves the same window with Ceres instead
//     (the reference). Mapping mode (landmarks are variables): Ceres;
//  4. marginalizes keyframes older than window_s (Schur complement,
//     marginalization.h) into the prior on the oldest kept keyframe; a
//     keyframe held by HoldKeyframe (it carries an active loop closure) is
//     not marginalized, nor is anything newer (the window is a chain and is
//     marginalized from its old end), until it is released;
//  5. the newest pose's covariance is the inverse of the last block of the
//     chain's forward elimination (exact for the chain; in mapping mode the
//     landmarks are treated as known).
//
// Landmarks stay in the atlas (unless the upkeep retires them): fixed in
// localization mode (a born one is refined by its own sightings),
// variables in mapping mode while a window keyframe observes them. When a
// keyframe is marginalized in mapping mode its landmark factors are dropped
// (not folded into the prior as if the landmarks were exact, which would
// anchor the prior to their current estimates); this keeps the prior on one
// pose and the memory bounded at the price of the information those factors
// carried about the pose chain. Mapped landmark covariances are the tracker's
// first-order fusion, and the newest-pose covariance in mapping mode treats
// the landmarks as known (optimistic). There are no loop-closure factors
// yet; HoldKeyframe is the hold-back their owner will use.
//
// Other relative sensors (a LiDAR scan match between consecutive keyframes)
// enter as an optional RelativePoseMeasurement per keyframe: a second
// between-factor next to the odometry, whose square-root information may be
// rank deficient (a corridor match carries nothing along the aisle).
//
// Memory: the window holds at most window_s of keyframes (more while a
// keyframe is held); everything else is the atlas. Not thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_SLIDING_WINDOW_SMOOTHER_H_
#define GROUNDLINE_LOCALIZATION_SLIDING_WINDOW_SMOOTHER_H_

#include <array>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_association.h"
#include "groundline/localization/floor_observation.h"
#include "groundline/localization/landmark_tracker.h"
#include "groundline/localization/marginalization.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/localization/pose_chain_solver.h"

namespace ceres {
class LossFunction;
}  // namespace ceres

namespace groundline::localization {

class GroundLineFactor;
class JunctionFactor;
class RelativePoseFactor;

enum class SmootherMode { kLocalization, kMapping };
// How the localization-mode window is solved: the block-tridiagonal chain
// solver, or Ceres (SPARSE_NORMAL_CHOLESKY, Levenberg-Marquardt) on the same
// factors. Mapping mode always uses Ceres.
enum class SmootherSolver { kChain, kCeres };

// Localization mode: keeping the atlas current while localizing on it
// (docs/atlas.md, "Keeping the atlas current"). Floor markings and
// junctions only; wall and rack faces are left as they are.
//   Birth: a marking that matches no landmark, and is not near one
//   (birth_novelty_chi2), is tracked (tracker) and
//   becomes a landmark after tracker.min_keyframes consistent sightings,
//   each made from a keyframe that is localized on the atlas: at least
//   birth_min_matches landmark factors, and a predicted position standard
//   deviation (largest axis) of at most birth_max_position_sigma_m (a lost
//   vehicle would map its error into the atlas). The new landmark's
//   covariance is the tracker's fusion, pose uncertainty included; it is
//   used at once, its covariance in its factors.
//   Retirement: a landmark is expected at a keyframe when at least
//   min_in_view_m of its extent (a junction: its point) lies inside the
//   frame's view (FloorObservations::view) by view_margin_m, and the frame
//   was read (at least one landmark factor). One expected and not matched
//   retire_after_misses times in a row is retired: no longer associated,
//   left out of CurrentAtlas(). A frame without a view is no evidence. The
//   count carries over drives in the atlas (AtlasLine::missed): a stop bar
//   in view for 3 keyframes a pass is retired after four passes, over one
//   drive or several.
// Each landmark seen gets its sightings record (AtlasLine::seen) updated.
struct AtlasUpkeepOptions {
  bool enabled = false;
  // The tentative tracks. A transverse marking (a stop bar, a joint) stays
  // in the camera's view for 2-4 keyframes as the vehicle passes it: 3
  // consistent sightings make a landmark.
  LandmarkTrackerOptions tracker = {.min_keyframes = 3, .max_gap_keyframes = 2};
  int retire_after_misses = 10;
  double view_margin_m = 0.15;
  double min_in_view_m = 0.5;
  int birth_min_matches = 1;
  double birth_max_position_sigma_m = 0.05;
  // An unmatched marking only just outside the gate of a landmark (d2 below
  // this: the 0.9999 quantile of 2 dof) is a poor sighting of that landmark,
  // not a new one: it is neither used nor tracked. Without it, three
  // sightings in a row just beyond the 0.99 gate of a kept line bear its
  // duplicate, which then takes its sightings until the original is retired.
  double birth_novelty_chi2 = 18.42;

  core::Status Validate() const;
};

struct SmootherOptions {
  SmootherMode mode = SmootherMode::kLocalization;
  double window_s = 120.0;  // keyframes older than this (vs the newest) are marginalized
  // Pseudo-Huber (SoftLOne) scale in whitened units (sigmas).
  double line_loss_scale = 2.0;
  double junction_loss_scale = 2.0;
  int max_iterations = 10;
  SmootherSolver solver = SmootherSolver::kChain;
  // kChain: stop when every component of the Gauss-Newton step is below this
  // (metres and radians).
  double step_tolerance = 1e-7;
  // kCeres and mapping mode: Ceres' relative function tolerance (and the
  // parameter and gradient tolerances, when tighter than their defaults).
  double ceres_tolerance = 1e-6;
  // Floors on the odometry increment's standard deviations (x, y and yaw
  // each), added in quadrature: the differential-drive model gives a turn
  // in place zero lateral variance, an unbounded information that the
  // window's block elimination cannot take. 0.3 mm: 1 mm held the lateral
  // variance of a 0.75 m keyframe at 1.4x the simulated encoders' (Monte
  // Carlo, tests/sim/keyframe_odometry_noise_test.cc) and, with a LiDAR
  // holding the lateral to ~1 mm, kept the newest pose's lateral covariance
  // ~9x too wide (zone D lines + LiDAR, lateral NEES mean 0.12).
  double odometry_sigma_floor_m = 3e-4;
  double odometry_sigma_floor_rad = 1e-4;
  AssociationOptions association;
  // Localization mode: the standard deviation of a wheel slip's spurious
  // travel on one wheel [m] (0: no slip hypothesis). A slip turns the
  // heading by travel / track at once, far in the tail of the Gaussian
  // odometry model, and the lines seen after it fail the gate. When no
  // observation of a keyframe passes the gate (and some were seen), they
  // are associated once more with the prediction covariance plus that of
  // one slip at the previous keyframe (SlipCovariance), and the result is
  // kept when at least slip_min_matches of them match; only the gate
  // changes, the odometry factor keeps its covariance.
  double slip_sigma_m = 0.0;
  int slip_min_matches = 2;
  // With slip_sigma_m > 0 and a RelativePoseMeasurement (the LiDAR): when
  // the odometry's motion and the measurement disagree beyond
  // slip_relative_chi2 (3 dof; the disagreement weighed by both
  // covariances, in the directions the measurement constrains), one of the
  // two is wrong. A slip of one wheel by s moves the motion by
  // (s/2, 0, +-s/track) where it happened; the best such slip (either
  // wheel; at the span's start, middle or end) is removed from the
  // disagreement. If what is left is within slip_residual_chi2, the span
  // had a slip: its odometry factor gets one slip's covariance
  // (SlipCovariance) added, so that a slip's heading jump is not averaged
  // into the pose (which then fails the gate of every line after it).
  // Otherwise no slip explains it and the measurement is taken for the
  // wrong one (a scan match aliased along an aisle, off by tens of cm): it
  // is left out of the window. So is a measurement that constrains one
  // direction only (the heading at an aisle's end): the slip's one
  // parameter explains any disagreement there, so the test cannot tell. slip_relative_chi2 0: never
  // test; slip_residual_chi2 0: every disagreement is taken for a slip.
  double slip_relative_chi2 = 21.1;  // the 0.9999 quantile of 3 dof
  double slip_residual_chi2 = 18.4;  // the 0.9999 quantile of 2 dof
  double track_m = 0.76;             // the wheel track of the slip hypothesis [m]
  // Localization mode, on an atlas whose covariances are stated
  // (Atlas::covariances_stated) and for landmarks estimated from a drive: a
  // line or junction factor's noise includes the landmark's own covariance
  // P, propagated into the vehicle frame at the predicted pose (the landmark
  // is held fixed, so its error would otherwise count as exact).
  bool landmark_covariance_in_factors = true;
  // One landmark's error is one error, however often it is seen: a rack
  // face beside the whole aisle is in every keyframe, and with P in each
  // factor anew its 2 cm would count as 2 cm / sqrt(K). With this on, each
  // of the K sightings of a landmark in the current pass (those in the
  // window, and those folded into the marginal prior since the landmark was
  // last out of the window) carries K P: together they hold P's
  // information once where P dominates, and all of the observations' where
  // it is negligible (the covariance-inflation bound for a shared error;
  // conservative in between). The window's factors are reweighted as K
  // grows; those already in the prior keep the K of their time.
  bool share_landmark_error = true;
  // Mapping mode: the tentative tracks of observations that match no
  // landmark (localization mode: upkeep.tracker).
  LandmarkTrackerOptions tracker;
  AtlasUpkeepOptions upkeep;  // localization mode

  core::Status Validate() const;
};

struct PoseEstimate {
  double stamp_s = 0.0;
  core::SE2 T_map_base;
  core::Matrix3 covariance = core::Matrix3::Zero();  // tangent space (x, y, yaw)
};

// The pose at the end of `motion` (relative to the keyframe), with the
// first-order covariance Ad(D^-1) Sigma_kf Ad(D^-1)^T + Sigma_D: the
// odometry-rate output between keyframes.
PoseEstimate PropagateFromKeyframe(const PoseEstimate& keyframe, const RelativeMotion& motion,
                                   double stamp_s);

// The covariance, in the tangent space at the end of `motion`, of one
// wheel slip of spurious travel ~N(0, slip_sigma_m^2) on either wheel at
// its start: (ds, dtheta) = (m / 2, +-m / track_m) there, carried along by
// Ad(T_start_end^-1).
core::Matrix3 SlipCovariance(const RelativeMotion& motion, double slip_sigma_m, double track_m);

// The disagreement r^T W r between an odometry motion and a relative
// measurement (r = Log(motion^-1 * measured), W = core::DifferenceInformation
// of their covariances) that is left once the one-wheel slip that best
// explains it is removed: the minimum over either wheel and a slip at the
// start, middle or end of the motion of r^T W r - (d^T W r)^2 / (d^T W d),
// d the slip's direction (1/2, 0, +-1/track) carried to the motion's end.
// The slip's size is bounded by what a wheel can slip over the motion: a
// spinning wheel slips at most what it read, a locked one what the vehicle
// drove; both are at most the outer wheel's travel, |ds| + |dtheta| track/2,
// plus max_slip_margin_m (a slip larger than that, say a quarter turn in
// half a metre, is no slip: it is the other measurement that is wrong).
double OneWheelSlipResidualChi2(const RelativeMotion& motion, const core::Vector3& r,
                                const core::Matrix3& W, double track_m, double max_slip_margin_m);

// A measured pose of the new keyframe seen from the previous one, T_prev_curr,
// from a sensor other than the wheels (a LiDAR scan match). S^T S is its
// information in the tangent space of T_prev_curr; rows of zeros where the
// sensor carries no information (lidar::MatchInformation::sqrt_information).
struct RelativePoseMeasurement {
  core::SE2 T_prev_curr;
  core::Matrix3 sqrt_information = core::Matrix3::Zero();
};

struct KeyframeHealth {
  double stamp_s = 0.0;
  int lines_observed = 0;
  int lines_used = 0;
  int lines_rejected = 0;  // outside every gate or ambiguous
  int lines_ambiguous = 0;
  int junctions_observed = 0;
  int junctions_used = 0;
  bool relative_measurement_used = false;  // a RelativePoseMeasurement entered the window
  bool slip_gate = false;  // associated under the slip hypothesis (SmootherOptions::slip_sigma_m)
  // The odometry disagreed with the relative measurement (slip_relative_chi2):
  // its factor was widened by one slip.
  bool slip_from_relative = false;
  // The disagreement was beyond slip_relative_chi2 and no slip explained it:
  // the relative measurement was left out.
  bool relative_rejected = false;
  double relative_chi2 = 0.0;  // that disagreement (0 without a measurement)
  // What is left of it once the best one-wheel slip is removed (computed
  // only beyond slip_relative_chi2; 0 otherwise).
  double slip_residual_chi2 = 0.0;
  int landmarks_added = 0;    // mapping mode; localization mode with upkeep
  int landmarks_retired = 0;  // localization mode with upkeep
  int window_size = 0;      // keyframes in the window after this update
  int iterations = 0;
  // The solve met its step tolerance (chain) or Ceres' convergence test;
  // false when it stopped at max_iterations (the estimate is then the last
  // pose set that lowered the cost).
  bool converged = false;
  double solve_time_s = 0.0;   // the window solve
  double update_time_s = 0.0;  // the whole AddKeyframe
};

class SlidingWindowSmoother {
 public:
  // options must be valid (asserted); the atlas must be valid (asserted).
  SlidingWindowSmoother(const SmootherOptions& options, Atlas atlas);
  ~SlidingWindowSmoother();

  // The first keyframe, with a prior of the given covariance (tangent space).
  void Initialize(double stamp_s, const core::SE2& T_map_base, const core::Matrix3& covariance);

  // A new keyframe at stamp_s, `motion` since the previous keyframe
  // (OdometryIntegrator::StartKeyframe()), observations taken at stamp_s,
  // and optionally a relative measurement from the previous keyframe by
  // another sensor (a LiDAR scan match).
  // Errors: a failed solve or marginalization (the keyframe is kept, the
  // estimate is the prediction); a non-finite relative measurement.
  core::Result<KeyframeHealth> AddKeyframe(
      double stamp_s, const RelativeMotion& motion, const FloorObservations& observations,
      const std::optional<RelativePoseMeasurement>& relative = std::nullopt);

  bool initialized() const { return !window_.empty(); }
  // The newest keyframe's estimate (requires initialized()).
  const PoseEstimate& Latest() const { return latest_; }
  // The atlas with the current landmark estimates (mapping mode: normalized;
  // upkeep: the landmarks born, without the retired ones).
  Atlas CurrentAtlas() const;
  // Upkeep: landmarks born and retired since construction.
  int LandmarksBorn() const { return landmarks_born_; }
  int LandmarksRetired() const { return landmarks_retired_; }
  int WindowSize() const { return static_cast<int>(window_.size()); }
  // The window's pose estimates, oldest first.
  std::vector<core::SE2> WindowPoses() const;
  // Holds (held = true) or releases the window keyframe of that stamp: a
  // held keyframe carries an active loop closure and is not marginalized,
  // nor is any newer one, until released (the window grows meanwhile).
  // False when no window keyframe has that stamp.
  bool HoldKeyframe(double stamp_s, bool held = true);

 private:
  template <typename Factor>
  struct LandmarkFactor {
    int landmark = 0;  // index into atlas lines or junctions
    std::unique_ptr<Factor> cost;
    // The observation's covariance and the landmark's (in the vehicle frame;
    // zero when the landmark is taken as exact), and the sightings count K
    // the weight was made with: noise = observation + K landmark.
    Eigen::Matrix2d observation_covariance = Eigen::Matrix2d::Zero();
    Eigen::Matrix2d landmark_covariance = Eigen::Matrix2d::Zero();
    int shared_by = 1;
  };
  // A keyframe's (or the prior's) linearized terms in the chain, kept until
  // its poses move (sliding_window_chain.cc): the unary factors on this pose
  // and the between factors from the previous one.
  struct ChainTerms {
    bool valid = false;
    std::array<double, 3> at{};           // this pose when linearized
    std::array<double, 3> at_previous{};  // the previous pose when linearized
    long prior_version = -1;              // the prior's terms: which prior
    double cost = 0.0;
    core::Matrix3 H_unary = core::Matrix3::Zero();  // the step's Hessian
    core::Matrix3 information_unary = core::Matrix3::Zero();
    core::Vector3 b_unary = core::Vector3::Zero();
    core::Matrix3 H_previous = core::Matrix3::Zero();  // between: (prev, prev)
    core::Matrix3 H_cross = core::Matrix3::Zero();     // (prev, this)
    core::Matrix3 H_current = core::Matrix3::Zero();   // (this, this)
    core::Vector3 b_previous = core::Vector3::Zero();
    core::Vector3 b_current = core::Vector3::Zero();
  };
  // The assembled chain and its eliminations; blocks before *_clean are
  // unchanged since they were last assembled / eliminated.
  struct ChainState {
    PoseChainSystem system;
    PoseChainSystem information;
    PoseChainElimination step_elimination;
    PoseChainElimination newest_elimination;
    int system_clean = 0;
    int step_clean = 0;
    int newest_clean = 0;
    ChainTerms prior;
  };
  struct Keyframe {
    double stamp_s = 0.0;
    bool held = false;  // HoldKeyframe
    ChainTerms chain;
    std::array<double, 3> pose{};
    // From the previous keyframe (empty for the first): the odometry factor,
    // then any RelativePoseMeasurement factor.
    std::vector<std::unique_ptr<RelativePoseFactor>> between;
    std::vector<LandmarkFactor<GroundLineFactor>> lines;
    std::vector<LandmarkFactor<JunctionFactor>> junctions;
  };

  // sliding_window_solve.cc: the window solve and the newest information.
  core::Status Solve(KeyframeHealth* health);
  core::Status SolveCeres(KeyframeHealth* health);
  core::Status SolveChain(KeyframeHealth* health);
  // sliding_window_chain.cc: chain_ at the current estimates (landmarks
  // fixed), relinearizing the terms whose poses moved (all of them when
  // relinearize_all); returns the robust cost.
  double LinearizeChain(bool relinearize_all);
  void LinearizeKeyframe(int index);
  void LinearizePrior();
  core::Result<core::Matrix3> NewestInformation();
  void InvalidateChain();

  core::Status MarginalizeOldest();
  std::vector<LinearizationFactor> UnaryFactors(const Keyframe& keyframe,
                                                std::vector<LinearizationVariable>* variables);
  // sliding_window_upkeep.cc: the sightings records and retirement
  // (AtlasUpkeepOptions) after a keyframe's association.
  void KeepAtlasCurrent(const FloorObservations& observations, const core::SE2& T_pred,
                        const std::vector<bool>& lines_matched,
                        const std::vector<bool>& junctions_matched, KeyframeHealth* health);
  // share_landmark_error: counts a keyframe's landmark factors in (added)
  // or out (marginalized) of the current pass, and reweights every factor
  // whose landmark's count changed (invalidating its chain terms).
  bool SharesLandmarkError() const {
    return options_.share_landmark_error && options_.mode == SmootherMode::kLocalization;
  }
  void CountSightings(const Keyframe& keyframe, bool added);
  core::Status ReweightSharedLandmarks();
  void AddLandmarkFactors(const FloorObservations& observations, const core::SE2& T_pred,
                          const core::Matrix3& covariance_pred,
                          const core::Matrix3& slip_covariance, Keyframe* keyframe,
                          KeyframeHealth* health);

  SmootherOptions options_;
  Atlas atlas_;
  // Parameter blocks of the landmarks (rho, alpha) / (x, y), parallel to the atlas.
  std::deque<std::array<double, 2>> line_blocks_;
  std::deque<std::array<double, 2>> junction_blocks_;
  std::deque<Keyframe> window_;
  std::unique_ptr<MarginalPriorFactor> prior_;  // on window_.front()
  std::unique_ptr<ceres::LossFunction> line_loss_;
  std::unique_ptr<ceres::LossFunction> junction_loss_;
  LandmarkTracker tracker_;
  // Upkeep, parallel to the atlas' lines / junctions.
  std::vector<bool> line_retired_;
  std::vector<bool> junction_retired_;
  std::vector<int> line_misses_;
  std::vector<int> junction_misses_;
  std::vector<bool> line_born_;
  std::vector<bool> junction_born_;
  // share_landmark_error, grown with the atlas: factors of each landmark in
  // the window, and in the current pass (window and prior).
  std::vector<int> line_in_window_;
  std::vector<int> junction_in_window_;
  std::vector<int> line_in_pass_;
  std::vector<int> junction_in_pass_;
  int landmarks_born_ = 0;
  int landmarks_retired_ = 0;
  PoseEstimate latest_;
  // The newest pose's marginal information from the last chain solve
  // (valid when newest_information_valid_).
  core::Matrix3 newest_information_ = core::Matrix3::Zero();
  bool newest_information_valid_ = false;
  ChainState chain_;
  long prior_version_ = 0;
  long keyframe_count_ = 0;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_SLIDING_WINDOW_SMOOTHER_H_
