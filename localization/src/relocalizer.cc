#include "groundline/localization/relocalizer.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <unordered_map>

#include "groundline/core/covariance.h"
#include "groundline/core/segment_distance.h"
#include "groundline/localization/floor_association.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::localization {
namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();
// The grid: observations lie within a few metres of the vehicle (the camera
// sees < 3 m ahead), so a cell lists what lies within kReachM of it.
constexpr double kCellM = 2.0;
constexpr double kReachM = 6.0;

// The observed extent [t_lo, t_hi] of points a, b along segment (s0, s1),
// measured from s0; false when the segment is degenerate.
bool ExtentAlong(const Eigen::Vector2d& s0, const Eigen::Vector2d& s1, const Eigen::Vector2d& a,
                 const Eigen::Vector2d& b, double* length, double* t_lo, double* t_hi) {
  const Eigen::Vector2d d = s1 - s0;
  *length = d.norm();
  if (*length < 1e-9) return false;
  const Eigen::Vector2d u = d / *length;
  const double ta = u.dot(a - s0), tb = u.dot(b - s0);
  *t_lo = std::min(ta, tb);
  *t_hi = std::max(ta, tb);
  return true;
}

}  // namespace

void Relocalizer::Information::Add(const Eigen::Vector2d& r, const Eigen::Matrix<double, 2, 3>& H,
                                   const Eigen::Matrix2d& R) {
  const Eigen::Matrix2d R_inv = R.inverse();
  this->H += H.transpose() * R_inv * H;
  b += H.transpose() * R_inv * r;
  ++count;
}

core::Status RelocalizerOptions::Validate() const {
  if (!(junction_line_distance_m > 0.0) || !(extent_margin_m >= 0.0) || !(birth_sigma_m > 0.0) ||
      !(birth_sigma_rad > 0.0) || !(duplicate_m > 0.0) || !(duplicate_rad > 0.0)) {
    return core::Status::Error(
        "relocalizer: junction_line_distance_m, birth sigmas and duplicate tolerances must be > 0, "
        "extent_margin_m >= 0");
  }
  if (!(line_rho_floor_m >= 0.0)) {
    return core::Status::Error("relocalizer: line_rho_floor_m must be >= 0");
  }
  if (!(gate_chi2 > 0.0) || !(unmatched_log_likelihood < -0.5 * gate_chi2)) {
    return core::Status::Error(
        "relocalizer: gate_chi2 must be > 0 and unmatched_log_likelihood < -gate_chi2 / 2 (a "
        "match must score better than no match)");
  }
  if (near_m && (!near_m->allFinite() || !(near_radius_m > 0.0) || !(near_drift_per_m >= 0.0) ||
                 !std::isfinite(near_radius_m) || !std::isfinite(near_drift_per_m))) {
    return core::Status::Error(
        "relocalizer: near_m must be finite, near_radius_m a finite number > 0, "
        "near_drift_per_m >= 0");
  }
  if (!(hint_tie_margin > 0.0) || !(hint_contradiction_margin >= hint_tie_margin)) {
    return core::Status::Error(
        "relocalizer: need hint_contradiction_margin >= hint_tie_margin > 0");
  }
  if (!(commit_margin > 0.0) || !(prune_margin > commit_margin) || !(min_travel_m >= 0.0) ||
      !(max_track_m > min_travel_m) || min_matched < 1 || !(min_match_share > 0.0) ||
      !(min_match_share <= 1.0)) {
    return core::Status::Error(
        "relocalizer: need commit_margin > 0, prune_margin > commit_margin, max_track_m > "
        "min_travel_m >= 0, min_matched >= 1, min_match_share in (0, 1]");
  }
  if (!(commit_max_sigma_m > 0.0) || !(commit_max_sigma_rad > 0.0)) {
    return core::Status::Error(
        "relocalizer: commit_max_sigma_m and commit_max_sigma_rad must be > 0");
  }
  return core::Status::Ok();
}

namespace {

// Poses bucketed in cells of cell_m x cell_m x cell_rad (heading cells
// wrapped at +-pi, each at least cell_rad wide): a pose within cell_m and
// cell_rad of another lies in one of the 27 cells around it, so finding
// duplicates among tens of thousands of hypotheses is linear, not quadratic.
class PoseBuckets {
 public:
  PoseBuckets(double cell_m, double cell_rad)
      : cell_m_(cell_m),
        yaw_cells_(std::max<std::int64_t>(
            1, static_cast<std::int64_t>(std::floor(2.0 * std::numbers::pi / cell_rad)))) {}

  void Add(const core::SE2& T, std::size_t index) { cells_[KeyOf(T)].push_back(index); }

  // True when pred(index) holds for a pose added in the cells around T.
  template <class Pred>
  bool AnyNear(const core::SE2& T, Pred&& pred) const {
    const Key k = KeyOf(T);
    std::array<std::int64_t, 3> yaws = {(k.yaw + yaw_cells_ - 1) % yaw_cells_, k.yaw,
                                        (k.yaw + 1) % yaw_cells_};
    const std::size_t n_yaws = yaw_cells_ >= 3 ? 3 : static_cast<std::size_t>(yaw_cells_);
    if (yaw_cells_ < 3) yaws = {0, yaw_cells_ - 1, 0};
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::size_t i = 0; i < n_yaws; ++i) {
          const auto it = cells_.find(Key{k.x + dx, k.y + dy, yaws[i]});
          if (it == cells_.end()) continue;
          for (std::size_t index : it->second) {
            if (pred(index)) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  struct Key {
    std::int64_t x, y, yaw;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      const auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v); };
      return std::hash<std::uint64_t>()(u(k.x) * 73856093u ^ u(k.y) * 19349663u ^
                                        u(k.yaw) * 83492791u);
    }
  };
  Key KeyOf(const core::SE2& T) const {
    const double turn = (core::WrapAngle(T.yaw()) + std::numbers::pi) / (2.0 * std::numbers::pi);
    return {static_cast<std::int64_t>(std::floor(T.x() / cell_m_)),
            static_cast<std::int64_t>(std::floor(T.y() / cell_m_)),
            std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(turn * yaw_cells_)), 0,
                                     yaw_cells_ - 1)};
  }

  double cell_m_;
  std::int64_t yaw_cells_;
  std::unordered_map<Key, std::vector<std::size_t>, KeyHash> cells_;
};

// The camera recognizes floor markings: wall and rack faces take no part.
Atlas FloorLandmarks(const Atlas& atlas) {
  Atlas floor = atlas;
  std::erase_if(floor.lines, [](const AtlasLine& l) { return core::IsFaceKind(l.kind); });
  return floor;
}

}  // namespace

Relocalizer::Relocalizer(const Atlas& atlas, const RelocalizerOptions& options)
    : atlas_(FloorLandmarks(atlas)), options_(options) {
  assert(atlas_.Validate().ok());
  assert(options_.Validate().ok());
  BuildGrid();
  junction_lines_.resize(atlas_.junctions.size());
  for (std::size_t j = 0; j < atlas_.junctions.size(); ++j) {
    const Eigen::Vector2d& p = atlas_.junctions[j].point_m;
    for (std::size_t l = 0; l < atlas_.lines.size(); ++l) {
      const AtlasLine& line = atlas_.lines[l];
      double length = 0.0, t_lo = 0.0, t_hi = 0.0;
      if (!ExtentAlong(line.endpoint_a_m, line.endpoint_b_m, p, p, &length, &t_lo, &t_hi)) continue;
      const bool within = t_lo > -options_.junction_line_distance_m &&
                          t_lo < length + options_.junction_line_distance_m;
      if (within && std::abs(perception::SignedDistance(line.line_map, p)) <
                        options_.junction_line_distance_m) {
        junction_lines_[j].push_back(l);
      }
    }
  }
}

void Relocalizer::BuildGrid() {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const AtlasLine& line : atlas_.lines) {
    lo = lo.cwiseMin(line.endpoint_a_m).cwiseMin(line.endpoint_b_m);
    hi = hi.cwiseMax(line.endpoint_a_m).cwiseMax(line.endpoint_b_m);
  }
  for (const AtlasJunction& junction : atlas_.junctions) {
    lo = lo.cwiseMin(junction.point_m);
    hi = hi.cwiseMax(junction.point_m);
  }
  if (!(lo.x() <= hi.x())) lo = hi = Eigen::Vector2d::Zero();
  grid_origin_m_ = lo - Eigen::Vector2d::Constant(kReachM);
  grid_cols_ = static_cast<int>(std::ceil((hi.x() - lo.x() + 2.0 * kReachM) / kCellM)) + 1;
  grid_rows_ = static_cast<int>(std::ceil((hi.y() - lo.y() + 2.0 * kReachM) / kCellM)) + 1;
  const std::size_t cells = static_cast<std::size_t>(grid_cols_) * grid_rows_;
  cell_lines_.assign(cells, {});
  cell_junctions_.assign(cells, {});
  const double reach = kReachM + kCellM;  // from any point of the cell
  for (int row = 0; row < grid_rows_; ++row) {
    for (int col = 0; col < grid_cols_; ++col) {
      const Eigen::Vector2d centre =
          grid_origin_m_ + kCellM * Eigen::Vector2d(col + 0.5, row + 0.5);
      const std::size_t cell = static_cast<std::size_t>(row) * grid_cols_ + col;
      for (std::size_t l = 0; l < atlas_.lines.size(); ++l) {
        const AtlasLine& line = atlas_.lines[l];
        if (core::DistanceToSegment(centre, line.endpoint_a_m, line.endpoint_b_m) < reach) {
          cell_lines_[cell].push_back(l);
        }
      }
      for (std::size_t j = 0; j < atlas_.junctions.size(); ++j) {
        if ((centre - atlas_.junctions[j].point_m).norm() < reach) {
          cell_junctions_[cell].push_back(j);
        }
      }
    }
  }
}

std::size_t Relocalizer::CellIndex(const Eigen::Vector2d& p_m) const {
  const Eigen::Vector2d q = (p_m - grid_origin_m_) / kCellM;
  const int col = std::clamp(static_cast<int>(std::floor(q.x())), 0, grid_cols_ - 1);
  const int row = std::clamp(static_cast<int>(std::floor(q.y())), 0, grid_rows_ - 1);
  return static_cast<std::size_t>(row) * grid_cols_ + col;
}

const std::vector<std::size_t>& Relocalizer::LinesNear(const Eigen::Vector2d& p_m) const {
  return cell_lines_[CellIndex(p_m)];
}

const std::vector<std::size_t>& Relocalizer::JunctionsNear(const Eigen::Vector2d& p_m) const {
  return cell_junctions_[CellIndex(p_m)];
}

Eigen::Vector2d Relocalizer::StartOf(const core::SE2& T_map_base) const {
  return (T_map_base * T_first_current_.Inverse()).translation();
}

bool Relocalizer::PriorAllows(const core::SE2& T_map_base) const {
  return !options_.near_m ||
         (StartOf(T_map_base) - *options_.near_m).norm() <=
             options_.near_radius_m + options_.near_drift_per_m * travel_total_m_;
}

bool Relocalizer::IsSamePose(const core::SE2& a, const core::SE2& b) const {
  return (a.translation() - b.translation()).norm() < options_.duplicate_m &&
         std::abs(core::WrapAngle(a.yaw() - b.yaw())) < options_.duplicate_rad;
}

std::optional<PoseEstimate> Relocalizer::AddFrame(double stamp_s, const RelativeMotion& motion,
                                                  const FloorObservations& observations) {
  if (committed_) return std::nullopt;
  if (started_) {
    T_first_current_ = T_first_current_ * motion.T_start_end;
    travel_total_m_ += motion.path_length_m;
  }
  started_ = true;
  if (!hypotheses_.empty()) {
    for (Hypothesis& h : hypotheses_) h.pose = PropagateFromKeyframe(h.pose, motion, stamp_s);
    status_.travel_since_seed_m += motion.path_length_m;
    if (options_.near_m && !best_excluded_) AddExcludedHypotheses(stamp_s, observations);
    for (Hypothesis& h : hypotheses_) Score(observations, &h);
    PruneAndUpdateStatus();
    if (std::optional<PoseEstimate> pose = TryCommit()) {
      committed_ = true;
      return pose;
    }
    // Lost: neither the best hypothesis the prior allows nor the best it
    // excludes explains the floor (the seed junction was not on the atlas).
    // A prior that only its exclusions explain is not lost: it is
    // contradicted, and the search goes on to gather evidence.
    const bool lost = !best_ || (IsLost(hypotheses_[*best_]) &&
                                 (!best_excluded_ || IsLost(hypotheses_[*best_excluded_])));
    // A drive still ambiguous after max_track_m reseeds; one whose start is
    // decided and only waits for its pose to become certain (rule 6) goes on
    // for as long again (its matches may never bring the pose there).
    const double track_m = Decided() ? 2.0 * options_.max_track_m : options_.max_track_m;
    if (lost || status_.travel_since_seed_m > track_m) {
      // The drive has one start: a seed whose frames contradict the prior
      // at its end contradicts it for the rest of the drive.
      earlier_seed_contradicted_ = earlier_seed_contradicted_ || seed_contradicted_;
      seed_contradicted_ = false;
      hypotheses_.clear();
      best_.reset();
      best_excluded_.reset();
    }
  }
  if (hypotheses_.empty()) Seed(stamp_s, observations);
  return std::nullopt;
}

core::Matrix3 Relocalizer::BirthCovariance() const {
  return core::Vector3(options_.birth_sigma_m * options_.birth_sigma_m,
                       options_.birth_sigma_m * options_.birth_sigma_m,
                       options_.birth_sigma_rad * options_.birth_sigma_rad)
      .asDiagonal();
}

void Relocalizer::SeedFromJunctions(double stamp_s, const FloorObservations& observations,
                                    std::vector<Hypothesis>* born) const {
  const core::Matrix3 birth_covariance = BirthCovariance();
  PoseBuckets buckets(options_.duplicate_m, options_.duplicate_rad);
  for (std::size_t i = 0; i < born->size(); ++i) buckets.Add((*born)[i].pose.T_map_base, i);
  for (const JunctionObservation& seen : observations.junctions) {
    for (const LineObservation& through : observations.lines) {
      if (std::abs(perception::SignedDistance(through.line_base, seen.point_base_m)) >
          options_.junction_line_distance_m) {
        continue;
      }
      for (std::size_t j = 0; j < atlas_.junctions.size(); ++j) {
        for (std::size_t l : junction_lines_[j]) {
          if (!KindsCompatible(through.kind, atlas_.lines[l].kind)) continue;
          const double base_yaw = atlas_.lines[l].line_map.alpha_rad - through.line_base.alpha_rad;
          for (double flip : {0.0, std::numbers::pi}) {
            const double yaw = core::WrapAngle(base_yaw + flip);
            const core::SE2 rotation(0.0, 0.0, yaw);
            const Eigen::Vector2d t = atlas_.junctions[j].point_m - rotation * seen.point_base_m;
            const core::SE2 T(t, yaw);
            const bool duplicate = buckets.AnyNear(
                T, [&](std::size_t i) { return IsSamePose((*born)[i].pose.T_map_base, T); });
            if (duplicate) continue;
            buckets.Add(T, born->size());
            born->push_back(NewHypothesis(stamp_s, T, birth_covariance));
          }
        }
      }
    }
  }
}

Relocalizer::Hypothesis Relocalizer::NewHypothesis(double stamp_s, const core::SE2& T,
                                                   const core::Matrix3& covariance) const {
  Hypothesis h;
  h.pose = {stamp_s, T, covariance};
  h.allowed = PriorAllows(T);
  return h;
}

void Relocalizer::AddExcludedHypotheses(double stamp_s, const FloorObservations& observations) {
  std::vector<Hypothesis> born;
  SeedFromJunctions(stamp_s, observations, &born);
  std::erase_if(born, [](const Hypothesis& h) { return h.allowed; });
  if (born.empty()) return;
  status_.born_excluded = born.size();
  // From this frame on, the hypotheses the prior allows and the newborn ones
  // are scored on the same frames.
  for (Hypothesis& h : hypotheses_) h.check = {};
  for (Hypothesis& h : born) hypotheses_.push_back(std::move(h));
}

void Relocalizer::Seed(double stamp_s, const FloorObservations& observations) {
  std::vector<Hypothesis> born;
  SeedFromJunctions(stamp_s, observations, &born);
  // Line seeds only early: the region they must cover grows with the travel.
  const bool any_allowed =
      std::any_of(born.begin(), born.end(), [](const Hypothesis& h) { return h.allowed; });
  if (!any_allowed && options_.near_m && travel_total_m_ <= options_.max_track_m) {
    SeedAlongLines(stamp_s, observations, &born);
  }
  // The hypotheses the prior excludes are kept only to check it against; a
  // seed with nothing the prior allows waits for a later frame.
  if (std::none_of(born.begin(), born.end(), [](const Hypothesis& h) { return h.allowed; })) {
    return;
  }
  status_.born_allowed = static_cast<std::size_t>(
      std::count_if(born.begin(), born.end(), [](const Hypothesis& h) { return h.allowed; }));
  status_.born_excluded = born.size() - status_.born_allowed;
  hypotheses_ = std::move(born);
  best_.reset();
  best_excluded_.reset();
  ++status_.seeds;
  status_.travel_since_seed_m = 0.0;
  for (Hypothesis& h : hypotheses_) Score(observations, &h);
  PruneAndUpdateStatus();
}

void Relocalizer::SeedAlongLines(double stamp_s, const FloorObservations& observations,
                                 std::vector<Hypothesis>* born) const {
  // The longest observed line fixes the heading and the offset from an atlas
  // line; the position along it is sampled every duplicate_m. Only poses
  // whose odometry leads back into the prior circle survive.
  const LineObservation* longest = nullptr;
  double longest_m = 0.0;
  for (const LineObservation& o : observations.lines) {
    const double length_m = (o.endpoint_b_base_m - o.endpoint_a_base_m).norm();
    if (length_m > longest_m) {
      longest = &o;
      longest_m = length_m;
    }
  }
  if (longest == nullptr) return;
  const double allowance_m = options_.near_radius_m + options_.near_drift_per_m * travel_total_m_;
  const double reach_m = allowance_m + travel_total_m_ + 3.0;  // where the vehicle can be now
  const Eigen::Vector2d seen_point =
      0.5 * (longest->endpoint_a_base_m + longest->endpoint_b_base_m);
  const core::Matrix3 birth_covariance = BirthCovariance();
  for (const AtlasLine& line : atlas_.lines) {
    if (!KindsCompatible(longest->kind, line.kind)) continue;
    const Eigen::Vector2d a = line.endpoint_a_m, b = line.endpoint_b_m;
    if (core::DistanceToSegment(*options_.near_m, a, b) > reach_m) continue;
    const double length_m = (b - a).norm();
    if (length_m < 1e-9) continue;
    const Eigen::Vector2d u = (b - a) / length_m;
    for (double flip : {0.0, std::numbers::pi}) {
      const double yaw =
          core::WrapAngle(line.line_map.alpha_rad - longest->line_base.alpha_rad + flip);
      const core::SE2 rotation(0.0, 0.0, yaw);
      // The seen midpoint lies on the atlas line at arc length s.
      for (double s = 0.0; s <= length_m; s += options_.duplicate_m) {
        const Eigen::Vector2d on_line = a + s * u;
        if ((on_line - *options_.near_m).norm() > reach_m) continue;
        const core::SE2 T(on_line - rotation * seen_point, yaw);
        if (((T * T_first_current_.Inverse()).translation() - *options_.near_m).norm() >
            allowance_m) {
          continue;
        }
        born->push_back(NewHypothesis(stamp_s, T, birth_covariance));
      }
    }
  }
}

void Relocalizer::Score(const FloorObservations& observations, Hypothesis* h) const {
  // Scored against the predicted pose; the matches then refine the pose
  // (one Gauss-Newton step in information form, i.e. a Kalman update), so a
  // hypothesis' uncertainty does not grow with the odometry while it
  // explains the floor.
  Information update;
  const auto add = [&](double ll) {
    const bool matched = ll > options_.unmatched_log_likelihood;
    h->log_likelihood += ll;
    (matched ? h->matched : h->unmatched) += 1;
    h->check.log_likelihood += ll;
    (matched ? h->check.matched : h->check.unmatched) += 1;
  };
  for (const LineObservation& o : observations.lines) add(LineLogLikelihood(*h, o, &update));
  for (const JunctionObservation& o : observations.junctions) {
    add(JunctionLogLikelihood(*h, o, &update));
  }
  ++h->frames_scored;
  if (update.count == 0) return;
  const Eigen::LDLT<core::Matrix3> prior(h->pose.covariance);
  if (prior.info() != Eigen::Success || !prior.isPositive()) return;
  const core::Matrix3 information = prior.solve(core::Matrix3::Identity()) + update.H;
  const Eigen::LDLT<core::Matrix3> posterior(information);
  if (posterior.info() != Eigen::Success || !posterior.isPositive()) return;
  const core::Vector3 delta = -posterior.solve(update.b);
  h->pose.T_map_base = h->pose.T_map_base.Plus(delta);
  h->pose.covariance = posterior.solve(core::Matrix3::Identity());
  h->pose.covariance = 0.5 * (h->pose.covariance + h->pose.covariance.transpose()).eval();
}

double Relocalizer::LineLogLikelihood(const Hypothesis& h, const LineObservation& o,
                                      Information* update) const {
  const core::SE2& T = h.pose.T_map_base;
  const Eigen::Vector2d a_map = T * o.endpoint_a_base_m;
  const Eigen::Vector2d b_map = T * o.endpoint_b_base_m;
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_r = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 3> best_H = Eigen::Matrix<double, 2, 3>::Zero();
  Eigen::Matrix2d best_R = Eigen::Matrix2d::Identity();
  for (std::size_t l : LinesNear(T.translation())) {
    const AtlasLine& line = atlas_.lines[l];
    if (!KindsCompatible(o.kind, line.kind)) continue;
    double length = 0.0, t_lo = 0.0, t_hi = 0.0;
    if (!ExtentAlong(line.endpoint_a_m, line.endpoint_b_m, a_map, b_map, &length, &t_lo, &t_hi) ||
        t_hi < -options_.extent_margin_m || t_lo > length + options_.extent_margin_m) {
      continue;
    }
    perception::Matrix23 J_T;
    Eigen::Matrix2d J_line;
    const perception::HesseLine predicted =
        perception::InverseTransformLine(T, line.line_map, &J_T, &J_line);
    Eigen::Matrix2d J_r;
    const Eigen::Vector2d r = perception::LineDifference(predicted, o.line_base, &J_r);
    const Eigen::Matrix<double, 2, 3> H = J_r * J_T;
    Eigen::Matrix2d R =
        o.covariance + J_r * J_line * line.covariance * J_line.transpose() * J_r.transpose();
    R(0, 0) += options_.line_rho_floor_m * options_.line_rho_floor_m;
    const double d2 = core::SquaredMahalanobis<2>(r, R + H * h.pose.covariance * H.transpose());
    if (d2 < best) {
      best = d2;
      best_r = r;
      best_H = H;
      best_R = R;
    }
  }
  if (!(best < options_.gate_chi2)) return options_.unmatched_log_likelihood;
  update->Add(best_r, best_H, best_R);
  return -0.5 * best;
}

double Relocalizer::JunctionLogLikelihood(const Hypothesis& h, const JunctionObservation& o,
                                          Information* update) const {
  const core::SE2& T = h.pose.T_map_base;
  core::Matrix23 H;
  core::Matrix2 rotation;
  const Eigen::Vector2d p_map = T.Act(o.point_base_m, &H, &rotation);
  const Eigen::Matrix2d R_seen = rotation * o.covariance * rotation.transpose();
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_r = Eigen::Vector2d::Zero();
  Eigen::Matrix2d best_R = Eigen::Matrix2d::Identity();
  for (std::size_t j : JunctionsNear(T.translation())) {
    const AtlasJunction& junction = atlas_.junctions[j];
    const Eigen::Vector2d r = p_map - junction.point_m;
    if (r.squaredNorm() > 1.0) continue;  // far beyond any gate
    const Eigen::Matrix2d R = R_seen + junction.covariance;
    const double d2 = core::SquaredMahalanobis<2>(r, R + H * h.pose.covariance * H.transpose());
    if (d2 < best) {
      best = d2;
      best_r = r;
      best_R = R;
    }
  }
  if (!(best < options_.gate_chi2)) return options_.unmatched_log_likelihood;
  update->Add(best_r, H, best_R);
  return -0.5 * best;
}

bool Relocalizer::IsLost(const Hypothesis& h) const {
  const int seen = h.matched + h.unmatched;
  return seen > 0 && h.frames_scored >= 3 && h.matched < options_.min_match_share * seen;
}

bool Relocalizer::MeetsMatchRule(int matched, int unmatched) const {
  return matched >= options_.min_matched &&
         matched >= options_.min_match_share * static_cast<double>(matched + unmatched);
}

void Relocalizer::PruneAndUpdateStatus() {
  std::sort(hypotheses_.begin(), hypotheses_.end(), [](const Hypothesis& a, const Hypothesis& b) {
    return a.log_likelihood > b.log_likelihood;
  });
  // Pruned against the best of their own kind (each kind was born at once,
  // so its log-likelihoods compare): the hypotheses the prior allows must
  // survive however much better an excluded one does, so that the report
  // can say how they compare.
  double best_allowed = kNone, best_excluded = kNone;
  for (const Hypothesis& h : hypotheses_) {
    double& best = h.allowed ? best_allowed : best_excluded;
    best = std::max(best, h.log_likelihood);
  }
  std::erase_if(hypotheses_, [&](const Hypothesis& h) {
    return h.log_likelihood < (h.allowed ? best_allowed : best_excluded) - options_.prune_margin;
  });
  // The refinement pulls hypotheses born a little apart onto one pose; the
  // runner-up must be a different pose, so merge into the better one.
  std::vector<Hypothesis> distinct;
  distinct.reserve(hypotheses_.size());
  PoseBuckets buckets(options_.duplicate_m, options_.duplicate_rad);
  for (Hypothesis& h : hypotheses_) {
    const bool same = buckets.AnyNear(h.pose.T_map_base, [&](std::size_t i) {
      return distinct[i].allowed == h.allowed &&
             IsSamePose(distinct[i].pose.T_map_base, h.pose.T_map_base);
    });
    if (same) continue;
    buckets.Add(h.pose.T_map_base, distinct.size());
    distinct.push_back(std::move(h));
  }
  hypotheses_ = std::move(distinct);

  best_.reset();
  best_excluded_.reset();
  std::optional<std::size_t> runner_up;
  for (std::size_t i = 0; i < hypotheses_.size(); ++i) {
    const Hypothesis& h = hypotheses_[i];
    if (!h.allowed) {
      if (!best_excluded_ ||
          h.check.log_likelihood > hypotheses_[*best_excluded_].check.log_likelihood) {
        best_excluded_ = i;
      }
    } else if (!best_) {
      best_ = i;
    } else if (!runner_up) {
      runner_up = i;
    }
  }
  status_.hypotheses = hypotheses_.size();
  const Hypothesis* best = best_ ? &hypotheses_[*best_] : nullptr;
  status_.best_log_likelihood = best ? best->log_likelihood : kNone;
  status_.runner_up_log_likelihood = runner_up ? hypotheses_[*runner_up].log_likelihood : kNone;
  status_.best_matched = best ? best->matched : 0;
  status_.best_unmatched = best ? best->unmatched : 0;
  // Rules 4 and 5 compare the two on the frames both were scored on.
  const Hypothesis* excluded = best_excluded_ ? &hypotheses_[*best_excluded_] : nullptr;
  const bool excluded_leads =
      excluded != nullptr &&
      (best == nullptr || excluded->check.log_likelihood > best->check.log_likelihood);
  const Hypothesis* overall = excluded_leads ? excluded : best;
  status_.overall_log_likelihood = overall ? overall->check.log_likelihood : kNone;
  status_.overall_matched = overall ? overall->check.matched : 0;
  status_.overall_unmatched = overall ? overall->check.unmatched : 0;
  status_.overall_start_m =
      overall ? StartOf(overall->pose.T_map_base) : Eigen::Vector2d::Zero().eval();
  status_.excluded_lead = !excluded ? kNone
                          : !best   ? std::numeric_limits<double>::infinity()
                                    : excluded->check.log_likelihood - best->check.log_likelihood;
  status_.look_elsewhere = status_.born_allowed > 0 && status_.born_excluded > status_.born_allowed
                               ? std::log(static_cast<double>(status_.born_excluded) /
                                          static_cast<double>(status_.born_allowed))
                               : 0.0;
  excluded_log_odds_ = status_.excluded_lead - status_.look_elsewhere;
  status_.excluded_log_odds = excluded_log_odds_;
  // Rule 4 counts only an exclusion that is itself a good explanation
  // (rule 3), not one that is merely less bad.
  status_.hint_contradicted = excluded != nullptr &&
                              MeetsMatchRule(excluded->check.matched, excluded->check.unmatched) &&
                              excluded_log_odds_ >= options_.hint_contradiction_margin;
  // The verdict is that of all the frames since the exclusions were born,
  // not of the first few: a handful of observations that perception got
  // wrong can cost the true hypothesis a lead of 15 that one of thousands
  // of twins elsewhere happens to fit, and the frames after take it back.
  // Once given, it stands until the lead falls below the tie margin, where
  // rule 5 lets the hypothesis the prior allows commit.
  if (status_.hint_contradicted) {
    seed_contradicted_ = true;
  } else if (excluded_log_odds_ < options_.hint_tie_margin) {
    seed_contradicted_ = false;
  }
  status_.hint_rejected = earlier_seed_contradicted_ || seed_contradicted_;
  if (status_.hint_contradicted) {
    ++status_.frames_hint_contradicted;
    status_.contradicted_best_log_likelihood = best ? best->check.log_likelihood : kNone;
    status_.contradicted_best_matched = best ? best->check.matched : 0;
    status_.contradicted_best_unmatched = best ? best->check.unmatched : 0;
    status_.contradicted_overall_log_likelihood = excluded->check.log_likelihood;
    status_.contradicted_overall_matched = excluded->check.matched;
    status_.contradicted_overall_unmatched = excluded->check.unmatched;
    status_.contradicted_overall_start_from_hint_m =
        (StartOf(excluded->pose.T_map_base) - *options_.near_m).norm();
  }
}

bool Relocalizer::Decided() const {
  // Rules 1, 3, 4 and 5 of the evidence rule of RelocalizerOptions.
  if (!best_ || status_.hint_rejected) return false;                 // rule 4
  if (excluded_log_odds_ >= options_.hint_tie_margin) return false;  // rule 5
  const Hypothesis& best = hypotheses_[*best_];
  return status_.best_log_likelihood - status_.runner_up_log_likelihood >= options_.commit_margin &&
         MeetsMatchRule(best.matched, best.unmatched);
}

std::optional<PoseEstimate> Relocalizer::TryCommit() const {
  if (!Decided() || status_.travel_since_seed_m < options_.min_travel_m) return std::nullopt;
  const PoseEstimate& pose = hypotheses_[*best_].pose;
  const core::Matrix3& C = pose.covariance;  // rule 6
  const double position_variance =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(C.topLeftCorner<2, 2>())
          .eigenvalues()
          .maxCoeff();
  if (position_variance > options_.commit_max_sigma_m * options_.commit_max_sigma_m ||
      C(2, 2) > options_.commit_max_sigma_rad * options_.commit_max_sigma_rad) {
    return std::nullopt;
  }
  return pose;
}

}  // namespace groundline::localization
