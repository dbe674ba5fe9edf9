// Changes of the floor camera's mount during a run, on demand, for the
// self-calibration work: the renderer draws every frame through the mount of
// its moment, while the dataset's calibration file keeps the nominal mount
// (what the vehicle believes) and ground_truth_extrinsics.csv records the true
// one (docs/dataset.md, format 1.1).
//
// Three physical causes, all expressed as changes of calibration::CameraMount
// (height_m, pitch_rad, roll_rad, yaw_rad, forward_m, lateral_m):
// - payload: a load on the forks pitches the chassis, a step of pitch (and a
//   little height) at a time;
// - tire wear: the camera sinks slowly as the wheels wear, a drift of height
//   per kilometre driven (or a step, e.g. after a wheel change);
// - knock: a collision bends the bracket, a sudden change of yaw, roll and
//   pitch at a time.
// Steps add to the nominal mount from their time on (several steps add up);
// the drift is rendered in steps of drift_step_m (each distinct mount costs
// the renderer a pixel table, ~2 s), and the recorded truth is exactly the
// rendered mount.
#ifndef GROUNDLINE_SIM_MOUNT_PERTURBATION_H_
#define GROUNDLINE_SIM_MOUNT_PERTURBATION_H_

#include <string>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/core/dataset_records.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"

namespace groundline::sim {

// A sudden change of the mount at at_s seconds after the start of the run;
// every field is added to the mount.
struct MountStep {
  std::string cause = "knock";  // "payload", "knock" or "height" (documentation)
  double at_s = 0.0;
  double height_m = 0.0;
  double pitch_rad = 0.0;  // positive: tilts further down
  double roll_rad = 0.0;
  double yaw_rad = 0.0;
  double forward_m = 0.0;
  double lateral_m = 0.0;
};

struct MountPerturbationOptions {
  std::vector<MountStep> steps;
  // Tire wear: height lost per kilometre driven, m/km (>= 0; 1e-3 = 1 mm/km).
  double height_loss_m_per_km = 0.0;
  // The drift changes the rendered mount in steps of this height.
  double drift_step_m = 2e-4;

  // Errors name the field ("steps[1].at_s: ..."); a step that would lift the
  // camera below the floor is found by MountSchedule.
  core::Status Validate() const;
};

// The true mount at elapsed_s into the run after distance_m of driving.
calibration::CameraMount PerturbedMount(const calibration::CameraMount& nominal,
                                        const MountPerturbationOptions& options, double elapsed_s,
                                        double distance_m);

// The mount over a run, piecewise constant: one record at the first
// ground-truth stamp, then one at each ground-truth sample where the mount
// differs from the previous record (steps and drift thus land on the 100 Hz
// ground-truth clock). Errors: invalid options, a mount that becomes invalid
// (e.g. the camera below the floor; the message names the stamp).
core::Result<std::vector<core::CameraExtrinsicsRecord>> MountSchedule(
    const calibration::CameraMount& nominal, const MountPerturbationOptions& options,
    const core::Trajectory& T_map_base);

// Conversions between the record and the mount (the stamp is the caller's).
calibration::CameraMount ToMount(const core::CameraExtrinsicsRecord& record);
core::CameraExtrinsicsRecord ToRecord(double stamp_s, const calibration::CameraMount& mount);

// Index of the record in force at stamp_s (the last with stamp <= stamp_s;
// the first for earlier stamps). The schedule must not be empty.
std::size_t RecordAt(const std::vector<core::CameraExtrinsicsRecord>& schedule, double stamp_s);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_MOUNT_PERTURBATION_H_
