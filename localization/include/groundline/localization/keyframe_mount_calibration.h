// The camera mount's self-calibration (calibration/mount_self_calibration.h)
// fed from the localizer's keyframes: each keyframe's floor lines with the
// wheel odometry's pose at its time. It sits beside the localizer, not in
// it: the motion it uses is the wheels' alone (KeyframeOutput::T_odom_base),
// never the estimate that the lines it calibrates pull on.
//
// Not thread-safe: the thread that receives the keyframes drives it.
#ifndef GROUNDLINE_LOCALIZATION_KEYFRAME_MOUNT_CALIBRATION_H_
#define GROUNDLINE_LOCALIZATION_KEYFRAME_MOUNT_CALIBRATION_H_

#include <nlohmann/json.hpp>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/mount_self_calibration.h"
#include "groundline/localization/localizer.h"

namespace groundline::localization {

class KeyframeMountCalibration {
 public:
  // The commissioned mount (the one the frames' BEV is made with) and valid
  // options (asserted).
  KeyframeMountCalibration(const calibration::CameraMount& commissioned,
                           const calibration::MountSelfCalibrationOptions& options);

  // A keyframe in time order. Keyframes without a frame advance nothing
  // (their motion is in the next one's odometry pose). Returns true when the
  // estimate changed.
  bool AddKeyframe(const KeyframeOutput& keyframe);

  const calibration::MountEstimate& estimate() const { return calibrator_.estimate(); }

 private:
  calibration::MountSelfCalibrator calibrator_;
  calibration::CameraMount mount_used_;
};

// The health fields of an estimate, in the extrinsics file's convention
// (docs/extrinsics.md): selfcal_pitch_deg, selfcal_roll_deg,
// selfcal_height_m, selfcal_yaw_deg, their 1-sigma selfcal_*_sigma_*,
// selfcal_alarm and, when raised, selfcal_alarm_message; selfcal_windows
// (windows fused so far) and selfcal_steps.
nlohmann::ordered_json MountEstimateJson(const calibration::MountEstimate& estimate);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_KEYFRAME_MOUNT_CALIBRATION_H_
