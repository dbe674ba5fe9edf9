#include "groundline/localization/keyframe_mount_calibration.h"

#include <cmath>

#include "groundline/core/angles.h"

namespace groundline::localization {

KeyframeMountCalibration::KeyframeMountCalibration(
    const calibration::CameraMount& commissioned,
    const calibration::MountSelfCalibrationOptions& options)
    : calibrator_(commissioned, options), mount_used_(commissioned) {}

bool KeyframeMountCalibration::AddKeyframe(const KeyframeOutput& keyframe) {
  if (!keyframe.frame_stamp_s) return false;
  calibration::MountFrame frame;
  frame.stamp_s = keyframe.stamp_s;
  frame.T_odom_base = keyframe.T_odom_base;
  frame.mount_used = mount_used_;
  frame.segments.reserve(keyframe.floor.lines.size());
  for (const LineObservation& line : keyframe.floor.lines) {
    frame.segments.push_back(
        {line.endpoint_a_base_m, line.endpoint_b_base_m, line.covariance});
  }
  return calibrator_.AddFrame(frame);
}

nlohmann::ordered_json MountEstimateJson(const calibration::MountEstimate& e) {
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
  return j;
}

}  // namespace groundline::localization
