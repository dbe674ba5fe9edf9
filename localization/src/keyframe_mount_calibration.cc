#include "groundline/localization/keyframe_mount_calibration.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include "groundline/core/angles.h"

namespace groundline::localization {

core::Status MountApplyOptions::Validate() const {
  if (!(std::isfinite(min_interval_s) && min_interval_s >= 0.0)) {
    return core::Status::Error("min_interval_s: expected a finite value >= 0 s");
  }
  if (!(max_step.allFinite() && (max_step.array() > 0.0).all())) {
    return core::Status::Error("max_step: expected 4 finite values > 0");
  }
  if (!(max_sigma.allFinite() && (max_sigma.array() > 0.0).all())) {
    return core::Status::Error("max_sigma: expected 4 finite values > 0");
  }
  if (!(std::isfinite(min_significance) && min_significance > 0.0)) {
    return core::Status::Error("min_significance: expected a finite value > 0 sigma");
  }
  if (!(min_change.allFinite() && (min_change.array() >= 0.0).all())) {
    return core::Status::Error("min_change: expected 4 finite values >= 0");
  }
  return core::Status::Ok();
}

KeyframeMountCalibration::KeyframeMountCalibration(
    const calibration::CameraMount& commissioned,
    const calibration::MountSelfCalibrationOptions& options, const MountApplyOptions& apply)
    : calibrator_(commissioned, options),
      apply_(apply),
      applied_(commissioned),
      observed_(commissioned) {
  assert(apply.Validate().ok());
}

core::Result<std::optional<KeyframeMountCalibration::MountUpdate>>
KeyframeMountCalibration::Restore(const calibration::SavedMountEstimate& saved) {
  if (core::Status s = calibrator_.Restore(saved.commissioned, saved.estimate); !s.ok()) return s;
  if (!apply_.enabled) return std::optional<MountUpdate>();
  return NextUpdate(/*bounded=*/false, /*may_move=*/true, /*always=*/false);
}

void KeyframeMountCalibration::SetAtlas(std::shared_ptr<const Atlas> atlas,
                                        const AssociationOptions& association) {
  assert(association.Validate().ok());
  atlas_ = std::move(atlas);
  association_ = association;
}

namespace {

// The atlas line's sigma across it at anchor_m (a point on it) and of its
// direction: LineCovarianceAbout's relation read backwards (a turn about the
// anchor moves rho by (Direction . anchor) dalpha).
calibration::MapLineRef MapLineRefAt(const AtlasLine& line, const Eigen::Vector2d& anchor_m) {
  const double t = line.line_map.Direction().dot(anchor_m);
  const Eigen::Vector2d j(1.0, -t);
  calibration::MapLineRef ref;
  ref.id = line.id;
  ref.rho_m = line.line_map.rho_m;
  ref.alpha_rad = line.line_map.alpha_rad;
  ref.sigma_m = std::sqrt(std::max(0.0, j.dot(line.covariance * j)));
  ref.sigma_rad = std::sqrt(std::max(0.0, line.covariance(1, 1)));
  return ref;
}

}  // namespace

bool KeyframeMountCalibration::AddKeyframe(const KeyframeOutput& keyframe) {
  if (!keyframe.frame_stamp_s) return false;
  calibration::MountFrame frame;
  frame.stamp_s = keyframe.stamp_s;
  frame.T_odom_base = keyframe.T_odom_base;
  frame.mount_used = keyframe.floor.camera_mount.value_or(calibrator_.commissioned());
  frame.segments.reserve(keyframe.floor.lines.size());
  for (const LineObservation& line : keyframe.floor.lines) {
    frame.segments.push_back({line.endpoint_a_base_m, line.endpoint_b_base_m,
                              line.covariance - line.mount_covariance, std::nullopt});
  }
  // The atlas lines they are sightings of, when the keyframe is localized on it.
  if (atlas_ && keyframe.has_covariance && keyframe.smoother) {
    const std::vector<Match> matches =
        AssociateLines(keyframe.floor.lines, *atlas_, keyframe.pose.T_map_base,
                       keyframe.pose.covariance, association_);
    for (const Match& m : matches) {
      if (m.landmark < 0 || m.ambiguous) continue;
      const LineObservation& line = keyframe.floor.lines[static_cast<std::size_t>(m.observation)];
      const Eigen::Vector2d middle =
          keyframe.pose.T_map_base * (0.5 * (line.endpoint_a_base_m + line.endpoint_b_base_m));
      frame.segments[static_cast<std::size_t>(m.observation)].map_line =
          MapLineRefAt(atlas_->lines[static_cast<std::size_t>(m.landmark)], middle);
    }
  }
  frame.flow = keyframe.floor.texture_flow;
  return calibrator_.AddFrame(frame);
}

std::optional<KeyframeMountCalibration::MountUpdate> KeyframeMountCalibration::DueMountUpdate(
    double stamp_s) {
  if (!apply_.enabled) return std::nullopt;
  const calibration::MountEstimate& e = calibrator_.estimate();
  // A window held as a possible step widens the lines at once (the mount may
  // already be that far off), and a confirmed or dropped one narrows them
  // again: neither waits for min_interval_s.
  const bool suspicion_changed =
      e.step_suspected != handed_suspicion_ ||
      (e.step_suspected && e.suspected_components != handed_suspected_components_);
  const bool may_move = !last_update_s_ || stamp_s - *last_update_s_ >= apply_.min_interval_s;
  if (!may_move && !suspicion_changed) return std::nullopt;
  const calibration::CameraMount before = applied_;
  const calibration::CameraMount observed_before = observed_;
  std::optional<MountUpdate> update = NextUpdate(/*bounded=*/true, may_move, suspicion_changed);
  if (update && (!calibration::SameMount(update->mount, before, 0.0) ||
                 !calibration::SameMount(update->observed, observed_before, 0.0))) {
    last_update_s_ = stamp_s;
  }
  return update;
}

std::optional<KeyframeMountCalibration::MountUpdate> KeyframeMountCalibration::NextUpdate(
    bool bounded, bool may_move, bool always) {
  const calibration::MountEstimate& e = calibrator_.estimate();
  const calibration::MountVector estimated = calibration::MountComponents(e.mount);
  const calibration::MountVector current = calibration::MountComponents(applied_);
  const calibration::MountVector commissioned_components =
      calibration::MountComponents(calibrator_.commissioned());
  calibration::MountVector target;
  std::array<bool, 4> follows{};
  for (int i = 0; i < 4; ++i) {
    const double sigma = std::sqrt(e.covariance(i, i));
    const double moved = std::abs(estimated(i) - commissioned_components(i));
    follows[i] = (apply_.follow_all_after_step && e.steps > 0) || sigma < apply_.max_sigma(i) ||
                 moved > apply_.min_significance * sigma;
    target(i) = follows[i] ? estimated(i) : commissioned_components(i);
  }
  // The observations: under the mount a suspected step showed (the mount is
  // most likely there), else under the target.
  const calibration::MountVector observed = e.step_suspected ? e.suspected_components : target;
  const calibration::MountVector observed_before = calibration::MountComponents(observed_);
  calibration::MountVector next = current;
  bool moves = false;
  for (int i = 0; may_move && i < 4; ++i) {
    // The observations follow at every update that may move ..
    if (std::abs(observed(i) - observed_before(i)) > apply_.min_change(i)) moves = true;
    // .. the BEV in bounded steps.
    const double change = target(i) - current(i);
    if (std::abs(change) <= apply_.min_change(i)) continue;
    next(i) = bounded ? current(i) + std::clamp(change, -apply_.max_step(i), apply_.max_step(i))
                      : target(i);
    moves = true;
  }
  if (!moves && !always) return std::nullopt;
  MountUpdate update;
  update.mount = calibration::WithMountComponents(applied_, next);
  update.observed = calibration::WithMountComponents(applied_, observed);
  if (e.step_suspected) {
    update.covariance = e.suspected_covariance;
  } else {
    // The estimate's uncertainty of the components that follow it.
    for (int i = 0; i < 4; ++i) {
      if (!follows[i]) continue;
      for (int j = 0; j < 4; ++j)
        if (follows[j]) update.covariance(i, j) = e.covariance(i, j);
    }
  }
  handed_suspicion_ = e.step_suspected;
  handed_suspected_components_ = e.suspected_components;
  applied_ = update.mount;
  observed_ = update.observed;
  ++mount_updates_;
  return update;
}

calibration::MountSelfCalibrationOptions WithOdometryCalibration(
    calibration::MountSelfCalibrationOptions options, const OdometryCalibration& odometry) {
  const core::Matrix3& C = odometry.drive_covariance;  // (left, right, track)
  const double radius_m = 0.5 * (odometry.drive.LeftRadius() + odometry.drive.RightRadius());
  const double mean_variance = 0.25 * (C(0, 0) + C(1, 1) + 2.0 * C(0, 1));
  const double difference_variance = C(0, 0) + C(1, 1) - 2.0 * C(0, 1);
  constexpr double kDefaultDifference = 1.4142135623730951e-3;  // sqrt(2) * 0.1 %
  options.motion_scale_sigma = std::sqrt(std::max(0.0, mean_variance)) / radius_m;
  options.motion_heading_sigma_rad *=
      std::sqrt(std::max(0.0, difference_variance)) / radius_m / kDefaultDifference;
  return options;
}

nlohmann::ordered_json MountEstimateJson(const calibration::MountEstimate& e,
                                         const calibration::CameraMount* applied,
                                         const calibration::CameraMount* observed) {
  using calibration::kMountHeight;
  using calibration::kMountPitch;
  using calibration::kMountRoll;
  using calibration::kMountYaw;
  const auto sigma = [&](int i) { return std::sqrt(e.covariance(i, i)); };
  nlohmann::ordered_json j;
  j["selfcal_pitch_deg"] = e.mount.pitch_rad * core::kRadToDeg;
  j["selfcal_roll_deg"] = e.mount.roll_rad * core::kRadToDeg;
  j["selfcal_height_m"] = e.mount.height_m;
  j["selfcal_yaw_deg"] = e.mount.yaw_rad * core::kRadToDeg;
  j["selfcal_pitch_sigma_deg"] = sigma(kMountPitch) * core::kRadToDeg;
  j["selfcal_roll_sigma_deg"] = sigma(kMountRoll) * core::kRadToDeg;
  j["selfcal_height_sigma_m"] = sigma(kMountHeight);
  j["selfcal_yaw_sigma_deg"] = sigma(kMountYaw) * core::kRadToDeg;
  j["selfcal_alarm"] = e.alarm;
  if (e.alarm) j["selfcal_alarm_message"] = e.alarm_message;
  j["selfcal_windows"] = e.windows_used;
  j["selfcal_steps"] = e.steps;
  j["selfcal_step_suspected"] = e.step_suspected;
  if (applied) {
    j["selfcal_applied_pitch_deg"] = applied->pitch_rad * core::kRadToDeg;
    j["selfcal_applied_roll_deg"] = applied->roll_rad * core::kRadToDeg;
    j["selfcal_applied_height_m"] = applied->height_m;
    j["selfcal_applied_yaw_deg"] = applied->yaw_rad * core::kRadToDeg;
  }
  if (observed) {
    j["selfcal_observed_pitch_deg"] = observed->pitch_rad * core::kRadToDeg;
    j["selfcal_observed_roll_deg"] = observed->roll_rad * core::kRadToDeg;
    j["selfcal_observed_height_m"] = observed->height_m;
    j["selfcal_observed_yaw_deg"] = observed->yaw_rad * core::kRadToDeg;
  }
  return j;
}

}  // namespace groundline::localization
