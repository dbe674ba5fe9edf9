#include "groundline/localization/localizer.h"

#include <cmath>
#include <limits>
#include <string>

#include "groundline/core/trajectory_association.h"
#include "localizer_impl.h"

namespace groundline::localization {

using internal::LocalizerImpl;

core::Status LocalizerOptions::Validate() const {
  if (core::Status s = keyframes.Validate(); !s.ok()) return s.WithContext("keyframes");
  if (core::Status s = texture_flow.Validate(); !s.ok()) return s.WithContext("texture_flow");
  if (core::Status s = noise.Validate(); !s.ok()) return s.WithContext("noise");
  if (core::Status s = smoother.Validate(); !s.ok()) return s.WithContext("smoother");
  if (core::Status s = scan_odometry.Validate(); !s.ok()) return s.WithContext("scan_odometry");
  if (core::Status s = scan_points.Validate(); !s.ok()) return s.WithContext("scan_points");
  if (core::Status s = relocalizer.Validate(); !s.ok()) return s.WithContext("relocalizer");
  if (core::Status s = mapper.Validate(); !s.ok()) return s;
  const std::pair<const char*, double> positive[] = {
      {"blind_keyframe_m", blind_keyframe_m},
      {"odometry_history_s", odometry_history_s},
      {"max_odometry_gap_s", max_odometry_gap_s},
      {"max_frame_lag_s", max_frame_lag_s},
      {"stale_after_s", stale_after_s},
      {"lateral_variance_m2_per_m", lateral_variance_m2_per_m},
      {"max_scan_gap_s", max_scan_gap_s},
      {"deskew_motion_window_s", deskew_motion_window_s},
      {"odometry_gap_speed_mps", odometry_gap_speed_mps},
      {"odometry_gap_yaw_rate_radps", odometry_gap_yaw_rate_radps},
      {"frozen_speed_mps", frozen_speed_mps},
      {"max_sensor_lead_s", max_sensor_lead_s}};
  for (const auto& [name, value] : positive) {
    if (!(std::isfinite(value) && value > 0.0)) {
      return core::Status::Error(std::string("localizer option ") + name +
                                 ": expected a finite number > 0, got " + std::to_string(value));
    }
  }
  if (!(std::isfinite(slip_speed_difference_change_mps) &&
        slip_speed_difference_change_mps >= 0.0)) {
    return core::Status::Error(
        "localizer option slip_speed_difference_change_mps: expected >= 0 (0: off), got " +
        std::to_string(slip_speed_difference_change_mps));
  }
  if (!(std::isfinite(max_coast_s) && max_coast_s >= 0.0)) {
    return core::Status::Error("localizer option max_coast_s: expected >= 0, got " +
                               std::to_string(max_coast_s));
  }
  if (!(std::isfinite(reorder_tolerance_s) && reorder_tolerance_s >= 0.0)) {
    return core::Status::Error("localizer option reorder_tolerance_s: expected >= 0, got " +
                               std::to_string(reorder_tolerance_s));
  }
  if (!(deskew_motion_window_s < odometry_history_s)) {
    return core::Status::Error(
        "localizer option deskew_motion_window_s: expected less than odometry_history_s (" +
        std::to_string(odometry_history_s) + "), got " + std::to_string(deskew_motion_window_s));
  }
  if (lidar_local_map_scans < 0) {
    return core::Status::Error("localizer option lidar_local_map_scans: expected >= 0, got " +
                               std::to_string(lidar_local_map_scans));
  }
  if (clock_jump_readings < 2) {
    return core::Status::Error("localizer option clock_jump_readings: expected >= 2, got " +
                               std::to_string(clock_jump_readings));
  }
  if (!(std::isfinite(wheel_variance_m2_per_m) && wheel_variance_m2_per_m >= 0.0)) {
    return core::Status::Error("localizer option wheel_variance_m2_per_m: expected >= 0, got " +
                               std::to_string(wheel_variance_m2_per_m));
  }
  return core::Status::Ok();
}

LocalizerOptions LocalizerOptions::ForFusion() {
  LocalizerOptions options;
  options.mode = LocalizerMode::kLines;
  options.use_lidar = true;
  options.use_wall_lines = true;
  // The simulated vehicle's random wheel travel error without its slips
  // (docs/localization.md, "Odometry noise"); slips go to the gate's slip
  // hypothesis (5.2 cm RMS).
  options.wheel_variance_m2_per_m = 1.0e-5;
  options.lateral_variance_m2_per_m = 1.0e-7;
  options.smoother.slip_sigma_m = 0.052;
  return options;
}

Localizer::Localizer(std::unique_ptr<LocalizerImpl> impl) : impl_(std::move(impl)) {}
Localizer::~Localizer() = default;

core::Result<std::unique_ptr<Localizer>> Localizer::Create(const LocalizerOptions& options,
                                                           LocalizerSetup setup) {
  core::Result<std::unique_ptr<LocalizerImpl>> impl =
      LocalizerImpl::Create(options, std::move(setup));
  if (!impl.ok()) return impl.status();
  return std::unique_ptr<Localizer>(new Localizer(std::move(*impl)));
}

core::Status Localizer::SetInitialPose(double stamp_s, const core::SE2& T_map_base,
                                       const core::Matrix3& covariance) {
  return impl_->SetInitialPose(stamp_s + impl_->clock_offset_s, T_map_base, covariance);
}
core::Status Localizer::RequestRelocalization() { return impl_->RequestRelocalization(); }
bool Localizer::started() const { return impl_->started; }
core::Status Localizer::SetCameraMount(const calibration::CameraMount& mount,
                                       const Eigen::Matrix4d& covariance,
                                       const std::optional<calibration::CameraMount>& observed) {
  if (!impl_->setup.camera) {
    return core::Status::Error("set camera mount: the localizer has no camera front end");
  }
  core::Result<FloorFrontEnd> rebuilt = impl_->setup.camera->WithMount(mount, covariance, observed);
  if (!rebuilt.ok()) return rebuilt.status();
  impl_->setup.camera = std::make_shared<const FloorFrontEnd>(std::move(rebuilt).value());
  return core::Status::Ok();
}
const std::optional<PoseEstimate>& Localizer::relocalized() const { return impl_->relocalized; }
const RelocalizerStatus* Localizer::relocalizer_status() const {
  return impl_->relocalizer ? &impl_->relocalizer->status() : nullptr;
}
// The implementation runs on its own continuous time (localizer_impl.h,
// clock_offset_s); the stamps the caller sees are the source's.
std::optional<KeyframeOutput> Localizer::AddWheelReading(const core::WheelEncoderReading& r) {
  std::optional<KeyframeOutput> out = impl_->AddWheelReading(r);
  if (out) impl_->ToSourceTime(*out);
  return out;
}
std::optional<KeyframeOutput> Localizer::AddOdometryIncrement(double stamp_s,
                                                              const core::SE2& T_prev_curr) {
  const WheelAngleIncrement wheels = WheelsFromIncrement(impl_->setup.drive, T_prev_curr);
  return impl_->AddWheelReading({stamp_s, wheels.left_rad, wheels.right_rad});
}
void Localizer::AddFrame(double stamp_s, FrameLoader load) {
  impl_->AddFrame(stamp_s + impl_->clock_offset_s, std::move(load), std::nullopt);
}
void Localizer::AddFloorObservations(ConvertedObservations observations) {
  observations.observations.stamp_s += impl_->clock_offset_s;
  const double stamp_s = observations.observations.stamp_s;
  impl_->AddFrame(stamp_s, nullptr, std::move(observations));
}
void Localizer::AddScan(core::LaserScan scan) {
  scan.stamp_s += impl_->clock_offset_s;
  impl_->AddScan(std::move(scan));
}
PoseEstimate Localizer::Current() const {
  PoseEstimate p = impl_->current;
  p.stamp_s -= impl_->clock_offset_s;
  return p;
}
std::optional<PoseEstimate> Localizer::PoseAt(double stamp_s) const {
  std::optional<PoseEstimate> p = impl_->PoseAt(stamp_s + impl_->clock_offset_s);
  if (p) p->stamp_s = stamp_s;
  return p;
}
RelativeMotion Localizer::SinceKeyframe() const {
  return impl_->odometry ? impl_->odometry->SinceKeyframe() : RelativeMotion();
}
core::Result<Atlas> Localizer::BuildAtlas(AtlasMapperReport* report) {
  if (!impl_->mapper) return CurrentAtlas();
  return impl_->mapper->Build(report);
}

core::Trajectory Localizer::MappedTrajectory(bool lidar_only) const {
  if (!impl_->mapper) return {};
  return lidar_only ? impl_->mapper->lidar_trajectory() : impl_->mapper->keyframe_trajectory();
}

Atlas Localizer::CurrentAtlas() const {
  return impl_->smoother ? impl_->smoother->CurrentAtlas() : impl_->setup.atlas;
}
const LocalizerCounters& Localizer::counters() const { return impl_->counters; }
SensorState Localizer::Sensors() const { return impl_->Sensors(); }
double Localizer::path_length_m() const { return impl_->path_length_m; }
const LocalizerOptions& Localizer::options() const { return impl_->options; }

}  // namespace groundline::localization
