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

#include <memory>
#include <optional>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/mount_estimate_file.h"
#include "groundline/calibration/mount_self_calibration.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_association.h"
#include "groundline/localization/localizer.h"
#include "groundline/localization/odometry_calibration.h"

namespace groundline::localization {

// When and how far the bird's-eye view follows the estimate. The BEV is
// rebuilt with the estimated mount at a bounded rate and in bounded steps, so
// that it never jumps: the lines of consecutive keyframes move by at most
// what one step of the mount moves them (0.2 deg of pitch: about 1.5 cm 2 m
// ahead), and a 1 deg payload step is applied over five rebuilds.
struct MountApplyOptions {
  bool enabled = true;
  double min_interval_s = 1.0;  // at most one rebuild per this much time
  // The largest change of a component per rebuild (pitch_rad, roll_rad,
  // height_m, yaw_rad).
  calibration::MountVector max_step =
      (calibration::MountVector() << 0.0035, 0.0035, 0.003, 0.0035).finished();  // 0.2 deg, 3 mm
  // A component follows the estimate while the estimate lies more than
  // min_significance sigma from the commissioned value (the drive shows that
  // it moved: a payload's pitch, seen in a rack aisle only through joints
  // crossing the view, is that sure within about a minute), or while its
  // sigma is below max_sigma (the estimate is as good as a commissioning).
  // Otherwise the BEV goes back to, or stays on, the commissioned value: an
  // estimate that is mostly its wide start (yaw on a straight aisle), or that
  // wanders within its noise about an unchanged mount, is not applied.
  calibration::MountVector max_sigma =
      (calibration::MountVector() << 0.00035, 0.00035, 0.0005, 0.00035).finished();  // 0.02 deg, 0.5 mm
  double min_significance = 3.0;
  // Once the estimator has found a step (a payload, a knock: the mount moved
  // away from its commissioning), every component follows the estimate: the
  // commissioned value is no longer known to be right for any of them, and
  // a payload lowers the camera by a millimetre or two, below what the
  // significance test sees against the wheels' scale error, while the
  // commissioned height is then further from the truth than the estimate.
  bool follow_all_after_step = true;
  // A rebuild only when a component would move by more than this (smaller
  // changes are below what perception resolves).
  calibration::MountVector min_change =
      (calibration::MountVector() << 0.00017, 0.00017, 0.0002, 0.00035).finished();  // 0.01 deg, 0.2 mm, 0.02 deg

  core::Status Validate() const;
};

class KeyframeMountCalibration {
 public:
  // The commissioned mount (the one the first frames' BEV is made with) and
  // valid options (asserted).
  KeyframeMountCalibration(const calibration::CameraMount& commissioned,
                           const calibration::MountSelfCalibrationOptions& options,
                           const MountApplyOptions& apply = {});

  // The atlas the vehicle localizes on (the localizer's kLines): each
  // keyframe's lines are associated with its lines at the keyframe's pose
  // estimate (floor_association.h, `association`), and the estimator ties
  // markings seen together to the atlas's angle and distance between them
  // (calibration::MapLineRef: pose-free, so the pose the lines pulled on
  // cannot confirm the mount they were read under). The distance between two
  // parallel markings is the view's scale, so the height, independently of
  // the wheels. Null: none (the default).
  void SetAtlas(std::shared_ptr<const Atlas> atlas, const AssociationOptions& association = {});

  // A keyframe in time order. Keyframes without a frame advance nothing
  // (their motion is in the next one's odometry pose). The frame's lines are
  // under the mount its observations carry (FloorObservations::camera_mount;
  // unset: the commissioned one), weighed by perception's own covariance
  // (LineObservation::mount_covariance taken out). Returns true when the
  // estimate changed.
  bool AddKeyframe(const KeyframeOutput& keyframe);

  // The mount to rebuild the BEV with at stamp_s, when a rebuild is due
  // (MountApplyOptions), and the mount the observations are to be expressed
  // under: the best estimate, which the BEV reaches only in bounded steps.
  // Its components that follow the estimate are the estimate's (the others
  // the commissioned ones), with the estimate's covariance of them (the
  // others' is zero: the commissioning's accuracy is in perception's
  // presets). While the estimator holds a window or frame pair as a possible
  // step (MountEstimate::step_suspected), the observations are expressed
  // under the mount the suspect showed, with its covariance (what a restart
  // with it would give): a joint seen between a payload and its
  // confirmation is read under the mount the floor's texture shows, instead
  // of under the old one (4 cm off 2 m ahead for 0.5 deg of pitch) or
  // widened until it no longer corrects anything. An update is handed out
  // when the suspicion comes and when it goes, at once. The caller
  // rebuilds (Localizer::SetCameraMount, the service's camera stage); this
  // object takes the mount as applied.
  struct MountUpdate {
    calibration::CameraMount mount;                        // the BEV's
    calibration::CameraMount observed;                     // the observations'
    Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // about `observed`
  };
  std::optional<MountUpdate> DueMountUpdate(double stamp_s);

  // Continues from a saved estimate (calibration/mount_estimate_file.h,
  // MountSelfCalibrator::Restore's errors). Returns the mount to build the
  // BEV with from the start, when it differs from the commissioned one: the
  // saved estimate's components that follow it, whole (no frame has been
  // seen under another mount, so there is nothing to jump from).
  core::Result<std::optional<MountUpdate>> Restore(const calibration::SavedMountEstimate& saved);
  const calibration::MountEstimate& estimate() const { return calibrator_.estimate(); }
  const calibration::CameraMount& commissioned() const { return calibrator_.commissioned(); }
  // The BEV's mount of the last update handed out (the commissioned one
  // before any), and its observed mount.
  const calibration::CameraMount& applied() const { return applied_; }
  const calibration::CameraMount& observed() const { return observed_; }
  int mount_updates() const { return mount_updates_; }

 private:
  // may_move: the mount may change (else only the covariance); always: an
  // update even when the mount does not change.
  std::optional<MountUpdate> NextUpdate(bool bounded, bool may_move, bool always);

  calibration::MountSelfCalibrator calibrator_;
  MountApplyOptions apply_;
  std::shared_ptr<const Atlas> atlas_;
  AssociationOptions association_;
  calibration::CameraMount applied_;
  calibration::CameraMount observed_;
  std::optional<double> last_update_s_;  // the last update that moved the mount
  // The suspicion of a step in the last update handed out.
  bool handed_suspicion_ = false;
  calibration::MountVector handed_suspected_components_ = calibration::MountVector::Zero();
  int mount_updates_ = 0;
};

// The self-calibration's options for a vehicle whose odometry was
// calibrated (odometry_calibration.h): the motion's systematic errors are
// the calibration's own uncertainty instead of the defaults' (each wheel
// 0.1 % off its nominal radius). motion_scale_sigma becomes the relative
// sigma of the mean radius; motion_heading_sigma_rad is scaled by the
// relative sigma of the radii's difference against the defaults'
// sqrt(2) * 0.1 % (the heading a window reads as yaw is proportional to it).
calibration::MountSelfCalibrationOptions WithOdometryCalibration(
    calibration::MountSelfCalibrationOptions options, const OdometryCalibration& odometry);

// The health fields of an estimate, in the extrinsics file's convention
// (docs/extrinsics.md): selfcal_pitch_deg, selfcal_roll_deg,
// selfcal_height_m, selfcal_yaw_deg, their 1-sigma selfcal_*_sigma_*,
// selfcal_alarm and, when raised, selfcal_alarm_message; selfcal_windows
// (windows fused so far), selfcal_steps and selfcal_step_suspected (a window
// held as a possible step); with `applied`, the mount the
// BEV is made with: selfcal_applied_pitch_deg, _roll_deg, _height_m, _yaw_deg;
// with `observed`, the mount the lines are read under (MountUpdate::observed):
// selfcal_observed_pitch_deg, _roll_deg, _height_m, _yaw_deg.
nlohmann::ordered_json MountEstimateJson(const calibration::MountEstimate& estimate,
                                         const calibration::CameraMount* applied = nullptr,
                                         const calibration::CameraMount* observed = nullptr);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_KEYFRAME_MOUNT_CALIBRATION_H_
