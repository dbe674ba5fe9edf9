#include "groundline/calibration/mount_self_calibration.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "groundline/core/angles.h"
#include "groundline/core/covariance.h"
#include "groundline/core/statistics.h"

namespace groundline::calibration {
namespace {

core::Status OptionError(const std::string& field, const std::string& expected) {
  return core::Status::Error("self-calibration option '" + field + "': expected " + expected);
}

bool PositiveFinite(double v) { return std::isfinite(v) && v > 0.0; }

const char* const kComponentNames[4] = {"pitch", "roll", "height", "yaw"};

}  // namespace

const char* MountComponentName(int component) { return kComponentNames[component]; }
const char* MountComponentUnit(int component) { return component == kMountHeight ? "mm" : "deg"; }
double MountComponentInUnit(int component, double value) {
  return component == kMountHeight ? value * 1000.0 : value * core::kRadToDeg;
}

MountVector MountComponents(const CameraMount& m) {
  return MountVector(m.pitch_rad, m.roll_rad, m.height_m, m.yaw_rad);
}

CameraMount WithMountComponents(CameraMount m, const MountVector& v) {
  m.pitch_rad = v(kMountPitch);
  m.roll_rad = v(kMountRoll);
  m.height_m = v(kMountHeight);
  m.yaw_rad = v(kMountYaw);
  return m;
}

core::Status MountSelfCalibrationOptions::Validate() const {
  if (!PositiveFinite(window_s)) return OptionError("window_s", "a time > 0 s");
  if (!(PositiveFinite(suspected_window_s) && suspected_window_s <= window_s))
    return OptionError("suspected_window_s", "a time > 0 s, at most window_s");
  if (min_window_frames < 2) return OptionError("min_window_frames", "at least 2");
  if (!PositiveFinite(max_frame_gap_s)) return OptionError("max_frame_gap_s", "a time > 0 s");
  if (!PositiveFinite(max_yaw_rate_rad_s)) return OptionError("max_yaw_rate_rad_s", "a rate > 0");
  if (!PositiveFinite(max_accel_mps2)) return OptionError("max_accel_mps2", "an acceleration > 0");
  if (!(std::isfinite(min_speed_mps) && min_speed_mps >= 0.0))
    return OptionError("min_speed_mps", "a speed >= 0");
  if (!PositiveFinite(min_segment_length_m))
    return OptionError("min_segment_length_m", "a length > 0");
  if (!PositiveFinite(min_segment_sigma_m))
    return OptionError("min_segment_sigma_m", "a sigma > 0");
  if (!PositiveFinite(associate_max_angle_rad))
    return OptionError("associate_max_angle_rad", "an angle > 0");
  if (!PositiveFinite(associate_max_distance_m))
    return OptionError("associate_max_distance_m", "a distance > 0");
  if (!(PositiveFinite(structure_gate_rad) && structure_gate_rad < 0.5))
    return OptionError("structure_gate_rad", "an angle in (0, 0.5) rad");
  if (!PositiveFinite(parallel_sigma_rad)) return OptionError("parallel_sigma_rad", "a sigma > 0");
  for (double s : known_spacings_m)
    if (!PositiveFinite(s)) return OptionError("known_spacings_m", "distances > 0");
  if (!PositiveFinite(spacing_gate_m)) return OptionError("spacing_gate_m", "a distance > 0");
  if (!PositiveFinite(spacing_sigma_m)) return OptionError("spacing_sigma_m", "a sigma > 0");
  if (!PositiveFinite(map_spacing_sigma_m)) {
    return OptionError("map_spacing_sigma_m", "a sigma > 0");
  }
  if (!PositiveFinite(odometry_sigma_m_per_sqrt_m))
    return OptionError("odometry_sigma_m_per_sqrt_m", "a sigma > 0");
  if (!PositiveFinite(odometry_sigma_rad_per_sqrt_m))
    return OptionError("odometry_sigma_rad_per_sqrt_m", "a sigma > 0");
  if (!(track_correlation >= 0.0 && track_correlation <= 1.0))
    return OptionError("track_correlation", "a correlation in [0, 1]");
  if (max_flow_points < 1) return OptionError("max_flow_points", "at least 1");
  if (min_flow_points < 1 || min_flow_points > max_flow_points)
    return OptionError("min_flow_points", "between 1 and max_flow_points");
  if (!PositiveFinite(flow_gate_m)) return OptionError("flow_gate_m", "a distance > 0");
  if (!PositiveFinite(flow_sigma_m)) return OptionError("flow_sigma_m", "a sigma > 0");
  if (!(flow_correlation >= 0.0 && flow_correlation <= 1.0))
    return OptionError("flow_correlation", "a correlation in [0, 1]");
  if (!(std::isfinite(motion_scale_sigma) && motion_scale_sigma >= 0.0 && motion_scale_sigma < 0.1))
    return OptionError("motion_scale_sigma", "a relative error in [0, 0.1)");
  if (!(std::isfinite(motion_heading_sigma_rad) && motion_heading_sigma_rad >= 0.0 &&
        motion_heading_sigma_rad < 0.1))
    return OptionError("motion_heading_sigma_rad", "an angle in [0, 0.1) rad");
  if (!PositiveFinite(loss_scale)) return OptionError("loss_scale", "a scale > 0");
  for (int i = 0; i < 4; ++i) {
    const std::string c = kComponentNames[i];
    if (!PositiveFinite(window_prior_sigma(i)))
      return OptionError("window_prior_sigma." + c, "> 0");
    if (!PositiveFinite(initial_sigma(i))) return OptionError("initial_sigma." + c, "> 0");
    if (!PositiveFinite(step_sigma(i))) return OptionError("step_sigma." + c, "> 0");
    if (!(std::isfinite(random_walk_per_sqrt_s(i)) && random_walk_per_sqrt_s(i) >= 0.0))
      return OptionError("random_walk_per_sqrt_s." + c, ">= 0");
    if (!PositiveFinite(alarm_threshold(i))) return OptionError("alarm_threshold." + c, "> 0");
  }
  if (!(step_probability > 0.5 && step_probability < 1.0))
    return OptionError("step_probability", "a probability in (0.5, 1)");
  if (step_windows < 1) return OptionError("step_windows", "at least 1");
  if (step_evidence_windows == 1 || step_evidence_windows < 0)
    return OptionError("step_evidence_windows", "0 (off) or at least 2");
  if (quick_step_frames < 0) return OptionError("quick_step_frames", "0 (off) or more");
  if (alarm_windows < 1) return OptionError("alarm_windows", "at least 1");
  if (!(std::isfinite(alarm_sigmas) && alarm_sigmas >= 0.0))
    return OptionError("alarm_sigmas", "a number >= 0");
  if (max_solver_iterations < 1) return OptionError("max_solver_iterations", "at least 1");
  return core::Status::Ok();
}

MountSelfCalibrator::MountSelfCalibrator(const CameraMount& commissioned,
                                         const MountSelfCalibrationOptions& options)
    : commissioned_(commissioned), options_(options) {
  assert(commissioned.Validate().ok());
  assert(options.Validate().ok());
  covariance_ = InitialCovariance();
  UpdateEstimate();
}

core::Status MountSelfCalibrator::Restore(const CameraMount& saved_commissioned,
                                          const MountEstimate& saved) {
  if (!SameMount(saved_commissioned, commissioned_)) {
    return core::Status::Error(
        "the saved mount estimate was made against another commissioned mount (the camera "
        "was recommissioned since): starting from the commissioned mount");
  }
  if (core::Status s = saved.mount.Validate(); !s.ok()) return s.WithContext("saved estimate");
  if (!core::IsCovariance(saved.covariance)) {
    return core::Status::Error("saved estimate: the covariance is not symmetric positive definite");
  }
  mean_ = MountComponents(saved.mount) - MountComponents(commissioned_);
  covariance_ = saved.covariance;
  // The saved covariance carries the motion's systematic errors
  // (UpdateEstimate).
  const MountVector systematic = SystematicVariance(saved.mount.height_m);
  for (int i = 0; i < 4; ++i) {
    if (covariance_(i, i) > 2.0 * systematic(i)) covariance_(i, i) -= systematic(i);
  }
  estimate_ = saved;
  estimate_.mount = commissioned_;
  // A knocked camera stays alarmed until it is recommissioned.
  alarm_streak_ = saved.alarm ? options_.alarm_windows - 1 : 0;
  UpdateEstimate();
  return core::Status::Ok();
}

bool MountSelfCalibrator::HasEvidence(const MountFrame& frame) const {
  for (const FloorSegment& s : frame.segments)
    if ((s.end_m - s.start_m).norm() >= options_.min_segment_length_m) return true;
  return false;
}

bool MountSelfCalibrator::HasFlowFrom(const MountFrame& frame, const MountFrame& previous) const {
  return options_.use_floor_flow &&
         static_cast<int>(frame.flow.points.size()) >= options_.min_flow_points &&
         FlowFollows(frame.flow, previous);
}

bool MountSelfCalibrator::FrameQualifies(const MountFrame& frame) const {
  if (recent_.empty()) return false;
  const MountFrame& prev = recent_.back();
  const double dt = frame.stamp_s - prev.stamp_s;
  if (!(dt > 0.0) || dt > options_.max_frame_gap_s) return false;
  const core::SE2 step = prev.T_odom_base.Between(frame.T_odom_base);
  const double speed = step.translation().norm() / dt;
  if (speed < options_.min_speed_mps) return false;
  if (std::abs(step.yaw()) / dt > options_.max_yaw_rate_rad_s) return false;
  if (recent_.size() >= 2) {
    const MountFrame& prev2 = recent_[recent_.size() - 2];
    const double dt0 = prev.stamp_s - prev2.stamp_s;
    if (dt0 > 0.0) {
      const double speed0 = prev2.T_odom_base.Between(prev.T_odom_base).translation().norm() / dt0;
      if (std::abs(speed - speed0) / (0.5 * (dt + dt0)) > options_.max_accel_mps2) return false;
    }
  }
  // A frame without a usable segment still qualifies: it carries the
  // motion, and a marking seen before and after it stays one track.
  return true;
}

bool MountSelfCalibrator::AddFrame(const MountFrame& frame) {
  if (!recent_.empty() && !(frame.stamp_s > recent_.back().stamp_s)) return false;
  ++estimate_.frames;
  bool changed = false;
  const bool qualifies = FrameQualifies(frame);
  if (!qualifies) ++estimate_.frames_gated;
  if (qualifies) CheckFramePair(frame);
  const bool gap =
      !window_.empty() && frame.stamp_s - window_.back().stamp_s > options_.max_frame_gap_s;
  if ((!qualifies || gap) && !window_.empty()) changed = CloseWindow();
  if (qualifies) {
    // A window starts with the frame before its first qualifying one: the
    // motion into that frame was judged with it.
    if (window_.empty() && recent_.back().stamp_s > last_windowed_stamp_s_)
      window_.push_back(recent_.back());
    window_.push_back(frame);
    // A window starts at its first frame with evidence (a usable segment, or
    // texture tracked from it into the next frame): frames before it hold
    // none, and a marking crossing the view (a joint is in view for about a
    // second) then fits in one window instead of being cut between two,
    // each with too few sightings.
    while (window_.size() > 1 && !HasEvidence(window_.front()) &&
           !HasFlowFrom(window_[1], window_.front()))
      window_.erase(window_.begin());
    const bool alarming_suspicion =
        estimate_.step_suspected &&
        ((estimate_.suspected_components - MountComponents(commissioned_)).cwiseAbs().array() >
         options_.alarm_threshold.array())
            .any();
    const double length_s = alarming_suspicion ? options_.suspected_window_s : options_.window_s;
    if (window_.back().stamp_s - window_.front().stamp_s >= length_s)
      changed = CloseWindow() || changed;
  }
  recent_.push_back(frame);
  while (recent_.size() > 2) recent_.pop_front();
  return changed;
}

void MountSelfCalibrator::CheckFramePair(const MountFrame& frame) {
  if (options_.quick_step_frames <= 0) return;
  if (!HasFlowFrom(frame, recent_.back())) {
    quick_streak_ = 0;
    return;
  }
  const MountWindowSolution pair =
      SolveMountWindow({recent_.back(), frame}, commissioned_, mean_, options_);
  int dims = 0;
  const double nis = pair.ok ? EvidenceNis(pair.information, pair.information_vector, mean_,
                                           covariance_, &dims)
                             : 0.0;
  const bool over = dims > 0 && nis > core::ChiSquareQuantile(dims, options_.step_probability);
  quick_streak_ = over ? quick_streak_ + 1 : 0;
  // The first pair over the gate straddles the step: `frame` is the first
  // under the new mount. The suspicion is read from the pairs after it,
  // together (one pair's height is a few millimetres off).
  if (quick_streak_ == 1) {
    streak_onset_s_ = frame.stamp_s;
    onset_pending_ = true;
    streak_evidence_ = MountWindowSolution{};
  }
  if (quick_streak_ >= std::min(2, options_.quick_step_frames)) {
    streak_evidence_.information += pair.information;
    streak_evidence_.information_vector += pair.information_vector;
  }
  // A window that holds the suspicion knows the mount better than the pairs.
  if (!suspect_.empty()) return;
  if (over) {
    // Before quick_step_frames pairs the evidence is not yet trusted (the
    // first pair straddles the step and cannot say where the mount went):
    // the suspicion is the estimate widened by a step.
    Suspect(quick_streak_ >= options_.quick_step_frames ? streak_evidence_ : MountWindowSolution{},
            /*from_frames=*/true);
  } else if (quick_suspicion_) {
    ClearSuspicion();  // the frames agree again and no window holds a step
  }
}

double EvidenceNis(const MountMatrix& information, const MountVector& information_vector,
                   const MountVector& mean, const MountMatrix& covariance, int* dims) {
  const Eigen::SelfAdjointEigenSolver<MountMatrix> eig(information);
  const double max_value = eig.eigenvalues().maxCoeff();
  Eigen::Matrix<double, 4, Eigen::Dynamic> U(4, 0);
  Eigen::VectorXd values(0);
  for (int i = 0; i < 4; ++i) {
    if (eig.eigenvalues()(i) > 1e-9 * max_value && eig.eigenvalues()(i) > 0.0) {
      U.conservativeResize(Eigen::NoChange, U.cols() + 1);
      U.col(U.cols() - 1) = eig.eigenvectors().col(i);
      values.conservativeResize(values.size() + 1);
      values(values.size() - 1) = eig.eigenvalues()(i);
    }
  }
  *dims = static_cast<int>(U.cols());
  if (U.cols() == 0) return 0.0;
  const Eigen::VectorXd z = (U.transpose() * information_vector).cwiseQuotient(values);
  const Eigen::VectorXd y = z - U.transpose() * mean;
  const Eigen::MatrixXd S =
      U.transpose() * covariance * U + Eigen::MatrixXd(values.cwiseInverse().asDiagonal());
  return core::SquaredMahalanobis<Eigen::Dynamic>(y, S);
}

bool MountSelfCalibrator::CloseWindow() {
  std::vector<MountFrame> frames;
  frames.swap(window_);
  last_windowed_stamp_s_ = frames.back().stamp_s;
  // A window that straddles a step shown by frame pairs holds frames under
  // two mounts, which no one mount explains: the texture tracked across the
  // step reads as a scale, a height error of millimetres, and a small step
  // is diluted below the gate. It is solved from the frames under the new
  // mount only. That holds for a streak whose suspicion was cleared since (a
  // 0.2 deg roll shows in the pair straddling it, and in too few pairs
  // after it for a suspicion to stand): no pair over the gate came on the
  // drives without drift, so the cut costs nothing there.
  if (frames.front().stamp_s < streak_onset_s_ && streak_onset_s_ <= frames.back().stamp_s) {
    std::erase_if(frames, [&](const MountFrame& f) { return f.stamp_s < streak_onset_s_; });
  }
  if (static_cast<int>(frames.size()) < options_.min_window_frames) {
    ++estimate_.windows_rejected;
    return false;
  }
  MountWindowSolution w = SolveMountWindow(frames, commissioned_, mean_, options_);
  if (!w.ok) {
    ++estimate_.windows_rejected;
    return false;
  }
  const double stamp_s = frames.back().stamp_s;
  // The random walk since the last fusion.
  if (last_fused_stamp_s_ >= 0.0) {
    const double dt = std::max(0.0, stamp_s - last_fused_stamp_s_);
    covariance_ += RandomWalkCovariance(dt);
  }
  int dims = 0;
  const double nis = EvidenceNis(w.information, w.information_vector, mean_, covariance_, &dims);
  if (dims == 0) {
    ++estimate_.windows_rejected;
    return false;
  }
  if (nis > core::ChiSquareQuantile(dims, options_.step_probability)) {
    suspect_.push_back({w, mean_, covariance_, stamp_s, frames.front().stamp_s});
    if (static_cast<int>(suspect_.size()) < options_.step_windows) {
      Suspect(w, /*from_frames=*/false);
      return false;
    }
    // A step: restart from the commissioned uncertainty. Where a frame pair
    // showed when the step came, every window since it is under the new
    // mount (the one open at it was cut there): the estimate restarts from
    // before the first of them with all of them. Otherwise with the last
    // window that showed the step (the first may straddle it, half of its
    // frames under the old mount).
    ++estimate_.steps;
    covariance_ = InitialCovariance();
    if (onset_pending_ && suspect_.front().first_stamp_s >= streak_onset_s_) {
      const std::size_t from = FirstRecentWindowAfterOnset();
      if (from < recent_windows_.size()) mean_ = recent_windows_[from].mean_before;
      FuseRecentWindowsAgain(from);
      for (const RecentWindow& s : suspect_) Fuse(s.window, s.stamp_s);
    } else {
      Fuse(suspect_.back().window, stamp_s);
      estimate_.windows_rejected += static_cast<int>(suspect_.size()) - 1;
    }
    onset_pending_ = false;
    // The windows that showed the step are updates in a row that disagree
    // with the mount from before: they count toward alarm_windows.
    alarm_streak_ = std::max(alarm_streak_, static_cast<int>(suspect_.size()) - 1);
    suspect_.clear();
    recent_windows_.clear();
    UpdateEstimate();
    return true;
  }
  // A lone outlier window before this one is dropped.
  estimate_.windows_rejected += static_cast<int>(suspect_.size());
  suspect_.clear();
  recent_windows_.push_back({w, mean_, covariance_, stamp_s, frames.front().stamp_s});
  Fuse(w, stamp_s);
  const std::size_t n_windows = static_cast<std::size_t>(options_.step_evidence_windows);
  if (n_windows > 0 && recent_windows_.size() > n_windows) recent_windows_.pop_front();
  bool step = false;
  if (n_windows > 0 && onset_pending_) {
    // A step small for one window whose onset a frame pair showed: the
    // windows since the onset together, none of which straddles it.
    const std::size_t from = FirstRecentWindowAfterOnset();
    const std::size_t after = recent_windows_.size() - from;
    if (after >= 2) step = StepInRecentWindows(from, from, stamp_s);
    if (step || after >= n_windows) onset_pending_ = false;
  }
  if (!step && n_windows > 0 && recent_windows_.size() == n_windows) {
    // A step small for one window: the last windows' evidence together
    // against the estimate from before them, but for the first (which may
    // straddle the step) in the restart.
    StepInRecentWindows(0, 1, stamp_s);
  }
  UpdateEstimate();
  return true;
}

bool MountSelfCalibrator::StepInRecentWindows(std::size_t from, std::size_t fuse_from,
                                              double stamp_s) {
  const RecentWindow& first = recent_windows_[from];
  MountMatrix information = MountMatrix::Zero();
  MountVector information_vector = MountVector::Zero();
  for (std::size_t i = from; i < recent_windows_.size(); ++i) {
    information += recent_windows_[i].window.information;
    information_vector += recent_windows_[i].window.information_vector;
  }
  // The estimate from before them, with the random walk since.
  const MountMatrix before =
      first.covariance_before + RandomWalkCovariance(std::max(0.0, stamp_s - first.stamp_s));
  int dims = 0;
  const double together =
      EvidenceNis(information, information_vector, first.mean_before, before, &dims);
  if (dims == 0 || together <= core::ChiSquareQuantile(dims, options_.step_probability)) {
    return false;
  }
  ++estimate_.steps;
  onset_pending_ = false;
  mean_ = first.mean_before;
  covariance_ = InitialCovariance();
  FuseRecentWindowsAgain(fuse_from);
  recent_windows_.clear();
  return true;
}

std::size_t MountSelfCalibrator::FirstRecentWindowAfterOnset() const {
  std::size_t from = 0;
  while (from < recent_windows_.size() && recent_windows_[from].first_stamp_s < streak_onset_s_) {
    ++from;
  }
  return from;
}

void MountSelfCalibrator::FuseRecentWindowsAgain(std::size_t from) {
  for (std::size_t i = from; i < recent_windows_.size(); ++i) {
    Fuse(recent_windows_[i].window, recent_windows_[i].stamp_s);
    --estimate_.windows_used;  // fused once already
    if (recent_windows_[i].window.map_spacings > 0) --estimate_.windows_with_atlas;
  }
}

namespace {

// The Gaussian (mean, covariance) fused with a window's evidence (its
// information and information vector about the same origin).
void FuseEvidence(const MountWindowSolution& w, MountVector* mean, MountMatrix* covariance) {
  const MountMatrix information = covariance->ldlt().solve(MountMatrix::Identity());
  const Eigen::LDLT<MountMatrix> fused(information + w.information);
  *mean = fused.solve(information * *mean + w.information_vector);
  *covariance = fused.solve(MountMatrix::Identity());
  *covariance = 0.5 * (*covariance + covariance->transpose()).eval();
}

}  // namespace

void MountSelfCalibrator::Fuse(const MountWindowSolution& w, double stamp_s) {
  FuseEvidence(w, &mean_, &covariance_);
  ++estimate_.windows_used;
  if (w.map_spacings > 0) ++estimate_.windows_with_atlas;
  last_fused_stamp_s_ = stamp_s;
  estimate_.last_update_s = stamp_s;
}

MountMatrix MountSelfCalibrator::InitialCovariance() const {
  return options_.initial_sigma.array().square().matrix().asDiagonal();
}

MountMatrix MountSelfCalibrator::RandomWalkCovariance(double dt_s) const {
  return (options_.random_walk_per_sqrt_s.array().square() * dt_s).matrix().asDiagonal();
}

void MountSelfCalibrator::Suspect(const MountWindowSolution& evidence, bool from_frames) {
  MountVector mean = mean_;
  MountMatrix covariance = covariance_;
  covariance.diagonal() += options_.step_sigma.array().square().matrix();
  FuseEvidence(evidence, &mean, &covariance);
  estimate_.step_suspected = true;
  estimate_.suspected_components = MountComponents(commissioned_) + mean;
  estimate_.suspected_covariance = covariance;
  estimate_.suspected_covariance.diagonal() +=
      SystematicVariance(estimate_.suspected_components(kMountHeight));
  quick_suspicion_ = from_frames;
}

void MountSelfCalibrator::ClearSuspicion() {
  estimate_.step_suspected = false;
  estimate_.suspected_components.setZero();
  estimate_.suspected_covariance.setZero();
  quick_suspicion_ = false;
}

MountVector MountSelfCalibrator::SystematicVariance(double height_m) const {
  MountVector v = MountVector::Zero();
  v(kMountHeight) = std::pow(height_m * options_.motion_scale_sigma, 2);
  v(kMountYaw) = std::pow(options_.motion_heading_sigma_rad, 2);
  return v;
}

void MountSelfCalibrator::UpdateEstimate() {
  ClearSuspicion();
  estimate_.mount = WithMountComponents(commissioned_, MountComponents(commissioned_) + mean_);
  estimate_.covariance = covariance_;
  estimate_.covariance.diagonal() += SystematicVariance(estimate_.mount.height_m);
  std::ostringstream what;
  bool alarm = false;
  for (int i = 0; i < 4; ++i) {
    const double change = mean_(i);
    const double sigma = std::sqrt(estimate_.covariance(i, i));
    // Confidently beyond the limit: an estimate near it with the uncertainty
    // of a few windows is no knock.
    if (std::abs(change) - options_.alarm_threshold(i) > options_.alarm_sigmas * sigma) {
      char text[160];
      std::snprintf(text, sizeof text, "%s changed by %+.2f %s (+-%.2f, limit %.2f)",
                    kComponentNames[i], MountComponentInUnit(i, change), MountComponentUnit(i),
                    MountComponentInUnit(i, sigma),
                    MountComponentInUnit(i, options_.alarm_threshold(i)));
      what << (alarm ? "; " : "") << text;
      alarm = true;
    }
  }
  // The condition must hold over alarm_windows updates in a row: one window
  // that is off (a marking that is not where paint usually is) is no knock.
  alarm_streak_ = alarm ? alarm_streak_ + 1 : 0;
  alarm = alarm_streak_ >= options_.alarm_windows;
  estimate_.alarm = alarm;
  estimate_.alarm_message = alarm ? "camera mount moved from its commissioning: " + what.str() +
                                        "; recommission the camera (groundline calibrate floor)"
                                  : "";
}

}  // namespace groundline::calibration
