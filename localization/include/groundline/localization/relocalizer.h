// Global localization on the atlas without an initial pose: the start is
// recognized from a junction and the lines around it.
//
// One frame's junction, with a line through it, fixes the pose up to the
// choice of atlas junction and of which of its lines the observed line is
// (and the line's two directions). Warehouses repeat: zone B has dozens of
// identical aisle mouths, so one frame cannot decide. The Relocalizer
// therefore keeps every such candidate pose as a hypothesis, moves them all
// with the odometry, and scores each frame's lines and junctions against the
// atlas from each hypothesis (Mahalanobis distance with the hypothesis' pose
// covariance, gated like association; an observation with no atlas
// counterpart costs a fixed log-likelihood). It commits only when one
// hypothesis leads every other by a margin after a minimum travel, and
// reseeds from a later junction when the best no longer explains the
// observations or the drive stays ambiguous for too long. With a coarse
// prior on the start and no junction in view, a line alone seeds: its
// heading and offset from each nearby atlas line, every position along it. A wrong commit is
// worse than a late one, so the defaults are conservative.
//
// A coarse prior is a claim, not a fact: an operator may name the wrong
// charger. The relocalizer therefore also keeps the hypotheses the prior
// excludes (born from junctions anywhere on the atlas) and scores them on
// the same frames; they never commit, but while one of them explains the
// floor much better than every hypothesis the prior allows, the prior is
// contradicted and nothing commits (RelocalizerOptions, "the evidence
// rule").
//
// Frames: hypotheses are T_map_base; observations in base_link (x forward,
// y left); metres and radians.
#ifndef GROUNDLINE_LOCALIZATION_RELOCALIZER_H_
#define GROUNDLINE_LOCALIZATION_RELOCALIZER_H_

#include <cstddef>
#include <numbers>
#include <optional>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_observation.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/localization/sliding_window_smoother.h"

namespace groundline::localization {

struct RelocalizerOptions {
  // An atlas line passes through an atlas junction, and an observed line
  // through an observed junction, when it comes this close to it.
  double junction_line_distance_m = 0.05;
  // An observed line matches an atlas line only where the marking is: its
  // extent (map frame) must overlap the atlas line's by this margin.
  double extent_margin_m = 0.30;
  // Pose uncertainty of a newborn hypothesis (1 sigma), from the junction's
  // and its line's measurement noise; grown by the odometry afterwards.
  double birth_sigma_m = 0.03;
  double birth_sigma_rad = 1.0 * std::numbers::pi / 180.0;
  // Standard deviation added (in quadrature) to the rho of every line
  // match's noise: the errors the likelihood does not model (the odometry's
  // scale drift between frames, perception biases such as a wide bar's edge),
  // which otherwise collapse a hypothesis' covariance until the true one
  // loses its matches (docs/atlas.md, "Scoring").
  double line_rho_floor_m = 0.05;
  // Association gate (chi-square, 2 dof) and the log-likelihood of an
  // observation that matches nothing; the latter must be below -gate/2 so a
  // match always scores better than no match.
  double gate_chi2 = 9.21;
  double unmatched_log_likelihood = -6.0;
  // The evidence rule. The relocalizer commits to its best hypothesis only
  // when all of these hold on the frames scored since the last seed (all
  // hypotheses of a seed are scored on the same frames, so their
  // log-likelihoods compare):
  //  1. it leads every other distinct hypothesis that the prior allows (all
  //     of them without a prior) by commit_margin in log-likelihood;
  //  2. min_travel_m has been driven since the seed;
  //  3. it matched at least min_matched observations and at least
  //     min_match_share of all its observations;
  //  4. with a prior (near_m): the prior is not contradicted. It is
  //     contradicted when a hypothesis it excludes, itself meeting rule 3,
  //     is more probable than the best it allows by hint_contradiction_margin
  //     or more in log-odds, on all the frames both were scored on: the
  //     floor seen is explained better by a start the prior rules out. The
  //     log-odds are the lead in log-likelihood less the look-elsewhere
  //     term log(born excluded / born allowed), floored at 0: every
  //     hypothesis born gets an equal share of the prior mass of its side
  //     (the start is as likely inside the prior's circle as outside it),
  //     and the best of the thousands of starts outside, born from every
  //     junction of the atlas, fits a few perception errors by luck more
  //     often than the best of the tens inside. The verdict is withdrawn
  //     when later frames bring the log-odds below hint_tie_margin (a few
  //     perception errors early in the drive, which a twin elsewhere happens
  //     to fit, are outweighed by what follows). The drive has one start, so
  //     a verdict standing when the search reseeds stands for the rest of
  //     the drive: nothing commits, and status() says why.
  //  5. with a prior: no hypothesis it excludes is more probable than the one
  //     that would commit by hint_tie_margin or more (the log-odds of rule
  //     4). The prior breaks ties between twins (a floor that repeats); it
  //     does not overrule the floor. A prior that lands on a twin of the
  //     true start (a floor that repeats with that offset) is not
  //     contradicted by anything the camera sees; nothing can tell it from
  //     the truth.
  //  6. the pose it would commit is certain enough for the smoother to take
  //     over: its position sigma (largest axis) is at most commit_max_sigma_m
  //     and its heading sigma at most commit_max_sigma_rad. A lead says
  //     which start; only the matches gathered say how well the pose is
  //     known. The committed covariance is the hypothesis' own (a Kalman
  //     update per frame): its heading errors on zone A drives with coarse
  //     perception were consistent with it (NEES about 1), reaching 0.8 deg
  //     at 0.29 deg sigma when the lead came before the matches had pinned
  //     the heading down.
  // A margin of 15 is a likelihood ratio of e^15 (3e6): about three
  // observations more explained than the runner-up (unmatched costs 6, a
  // match about 1).
  double commit_margin = 15.0;
  double min_travel_m = 2.0;
  int min_matched = 8;
  double min_match_share = 0.7;
  double hint_contradiction_margin = 15.0;
  // Half the cost of one unexplained observation: twins on a periodic floor
  // score alike to within their observation noise.
  double hint_tie_margin = 3.0;
  // Rule 6: 3 sigma within 9 cm and 0.9 deg; with coarse perception zone
  // A's hypotheses settle at 0.28-0.3 deg.
  double commit_max_sigma_m = 0.03;
  double commit_max_sigma_rad = 0.3 * std::numbers::pi / 180.0;
  // Hypotheses further than prune_margin below the best are dropped (with a
  // prior: those it allows below the best it allows, the others below the
  // best of all).
  double prune_margin = 40.0;
  // Reseed after this much travel without a decided start (rules 1, 3, 4
  // and 5: an ambiguous drive; a decided one waits up to twice as far for
  // rule 6), or
  // when the best hypothesis of all has a match share below min_match_share
  // after 3 scored frames (the seed junction was not on the atlas).
  double max_track_m = 40.0;
  // An optional coarse prior on where the drive STARTED (the fleet
  // manager's or the operator's "it is at charger 3"): a hypothesis is born
  // only if the odometry, run backwards from it to the first frame, lands
  // within near_radius_m + near_drift_per_m * (distance driven) of near_m.
  // Periodic floors (identical aisle mouths 4.65 m apart in zone B) cannot
  // be told apart without it.
  std::optional<Eigen::Vector2d> near_m;
  double near_radius_m = 2.0;
  double near_drift_per_m = 0.03;
  // Hypotheses closer than this at birth are one.
  double duplicate_m = 0.05;
  double duplicate_rad = 1.0 * std::numbers::pi / 180.0;

  core::Status Validate() const;
};

// The state of the search after the last frame. "Best" is the best
// hypothesis the prior allows (any hypothesis without a prior): the one that
// would commit. Log-likelihoods are -infinity where there is no hypothesis.
struct RelocalizerStatus {
  std::size_t hypotheses = 0;  // alive now, those the prior excludes included
  std::size_t seeds = 0;       // times hypotheses were (re)born
  double travel_since_seed_m = 0.0;
  double best_log_likelihood = 0.0;
  double runner_up_log_likelihood = 0.0;
  int best_matched = 0;
  int best_unmatched = 0;
  // With a prior: the best hypothesis of all (the prior's exclusions
  // included), and where its drive started (the odometry run back from it to
  // the first frame), map frame.
  double overall_log_likelihood = 0.0;
  int overall_matched = 0;
  int overall_unmatched = 0;
  Eigen::Vector2d overall_start_m = Eigen::Vector2d::Zero();
  // How far the best hypothesis the prior excludes leads the best it allows,
  // on the frames both were scored on (negative: it trails; -infinity:
  // there is none). The overall_* scores are on those frames too.
  double excluded_lead = 0.0;
  // That lead as log-odds (rules 4 and 5): less the look-elsewhere term.
  double excluded_log_odds = 0.0;
  double look_elsewhere = 0.0;
  // How many hypotheses the current seed gave birth to where the prior
  // allows the start, and elsewhere (the excluded ones, born to check it).
  std::size_t born_allowed = 0;
  std::size_t born_excluded = 0;
  // True after this frame's scores contradicted the prior.
  bool hint_contradicted = false;
  // The verdict of evidence rule 4 on the frames so far: the prior is
  // contradicted and nothing commits.
  bool hint_rejected = false;
  // Frames whose scores contradicted the prior, and the scores the last time
  // they did, kept across reseeds for the report at the end of the drive.
  std::size_t frames_hint_contradicted = 0;
  double contradicted_best_log_likelihood = 0.0;
  int contradicted_best_matched = 0;
  int contradicted_best_unmatched = 0;
  double contradicted_overall_log_likelihood = 0.0;
  int contradicted_overall_matched = 0;
  int contradicted_overall_unmatched = 0;
  double contradicted_overall_start_from_hint_m = 0.0;
};

class Relocalizer {
 public:
  // atlas must be valid (asserted); options must validate (asserted).
  Relocalizer(const Atlas& atlas, const RelocalizerOptions& options);

  // Feeds one frame: the odometry since the previous frame (ignored before
  // the first seed) and the frame's observations. Returns the committed pose
  // (at stamp_s, with covariance) once the drive is unambiguous; nullopt
  // while it is not. After a commit, further frames are ignored.
  std::optional<PoseEstimate> AddFrame(double stamp_s, const RelativeMotion& motion,
                                       const FloorObservations& observations);

  const RelocalizerStatus& status() const { return status_; }

 private:
  struct Hypothesis {
    PoseEstimate pose;
    double log_likelihood = 0.0;
    int matched = 0;
    int unmatched = 0;
    int frames_scored = 0;
    // Its start (the odometry run back to the first frame) lies where the
    // prior allows; always true without a prior.
    bool allowed = true;
    // The scores since the hypotheses the prior excludes were born, which
    // compare across the two kinds (rules 4 and 5).
    struct {
      double log_likelihood = 0.0;
      int matched = 0;
      int unmatched = 0;
    } check;
  };
  // The Gauss-Newton terms of one frame's matches: sum H^T R^-1 H and
  // sum H^T R^-1 r (r = predicted - measured, H = dr/d(right perturbation)).
  struct Information {
    core::Matrix3 H = core::Matrix3::Zero();
    core::Vector3 b = core::Vector3::Zero();
    int count = 0;
    void Add(const Eigen::Vector2d& r, const Eigen::Matrix<double, 2, 3>& H,
             const Eigen::Matrix2d& R);
  };
  void Seed(double stamp_s, const FloorObservations& observations);
  // Every pose that puts a seen junction (with a seen line through it) on an
  // atlas junction and the line on one of the atlas lines through it.
  void SeedFromJunctions(double stamp_s, const FloorObservations& observations,
                         std::vector<Hypothesis>* born) const;
  // With a prior and no excluded hypothesis alive (the seed was a line
  // seed): the excluded junction seeds of this frame, to check the prior.
  void AddExcludedHypotheses(double stamp_s, const FloorObservations& observations);
  Hypothesis NewHypothesis(double stamp_s, const core::SE2& T,
                           const core::Matrix3& covariance) const;
  core::Matrix3 BirthCovariance() const;
  bool IsLost(const Hypothesis& h) const;
  bool MeetsMatchRule(int matched, int unmatched) const;
  // With a prior and no junction in view, within the first max_track_m of
  // the drive: hypotheses from the frame's longest line against every atlas
  // line the vehicle can be near.
  void SeedAlongLines(double stamp_s, const FloorObservations& observations,
                      std::vector<Hypothesis>* born) const;
  void Score(const FloorObservations& observations, Hypothesis* h) const;
  // The observation's log-likelihood under h (-d^2/2 for the best atlas match
  // inside the gate, else unmatched_log_likelihood); a match adds its terms.
  double LineLogLikelihood(const Hypothesis& h, const LineObservation& o,
                           Information* update) const;
  double JunctionLogLikelihood(const Hypothesis& h, const JunctionObservation& o,
                               Information* update) const;
  // Drops hypotheses far below the best of their kind (allowed by the prior
  // or not), merges those of one kind on one pose, and fills status_.
  void PruneAndUpdateStatus();
  bool IsSamePose(const core::SE2& a, const core::SE2& b) const;
  // Where the drive started if the vehicle is at T_map_base now.
  Eigen::Vector2d StartOf(const core::SE2& T_map_base) const;
  bool PriorAllows(const core::SE2& T_map_base) const;
  // Rules 1, 3, 4 and 5 hold: the start is decided.
  bool Decided() const;
  // ... and rules 2 and 6: the pose to commit.
  std::optional<PoseEstimate> TryCommit() const;

  Atlas atlas_;
  RelocalizerOptions options_;
  // The atlas lines and junctions near a point: a uniform grid of
  // kCellM cells, each listing what lies within kReachM of it.
  const std::vector<std::size_t>& LinesNear(const Eigen::Vector2d& p_m) const;
  const std::vector<std::size_t>& JunctionsNear(const Eigen::Vector2d& p_m) const;
  void BuildGrid();
  std::size_t CellIndex(const Eigen::Vector2d& p_m) const;

  // For each atlas junction, the atlas lines through it.
  std::vector<std::vector<std::size_t>> junction_lines_;
  Eigen::Vector2d grid_origin_m_ = Eigen::Vector2d::Zero();
  int grid_cols_ = 0;
  int grid_rows_ = 0;
  std::vector<std::vector<std::size_t>> cell_lines_;
  std::vector<std::vector<std::size_t>> cell_junctions_;
  std::vector<Hypothesis> hypotheses_;
  // After PruneAndUpdateStatus: the best hypothesis the prior allows (by
  // log-likelihood), the best it excludes (by check.log_likelihood), and the
  // log-odds of the latter against the former on the frames both were scored
  // on (rules 4 and 5; -inf without an excluded one).
  std::optional<std::size_t> best_;
  std::optional<std::size_t> best_excluded_;
  double excluded_log_odds_ = 0.0;
  RelocalizerStatus status_;
  // Rule 4's verdict on the current seed's frames, and whether an earlier
  // seed ended with it.
  bool seed_contradicted_ = false;
  bool earlier_seed_contradicted_ = false;
  bool committed_ = false;
  // The odometry from the first frame to the current one.
  bool started_ = false;
  core::SE2 T_first_current_;
  double travel_total_m_ = 0.0;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_RELOCALIZER_H_
