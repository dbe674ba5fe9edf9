// A recorded run's self-calibration (mount_self_calibration.h) read back
// from its health.jsonl, compared with a truth where there is one (a
// simulated run's ground_truth_extrinsics.csv: evaluation only), and drawn as
// a page: pitch, roll, height and yaw over time with their 3-sigma bands,
// the truth, and the alarms (`groundline calibrate history`).
#ifndef GROUNDLINE_CALIBRATION_SELF_CALIBRATION_HISTORY_H_
#define GROUNDLINE_CALIBRATION_SELF_CALIBRATION_HISTORY_H_

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "groundline/calibration/mount_self_calibration.h"
#include "groundline/core/dataset_records.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

struct SelfCalibrationSample {
  double stamp_s = 0.0;
  MountVector value = MountVector::Zero();  // pitch_rad, roll_rad, height_m, yaw_rad
  MountVector sigma = MountVector::Zero();  // 1 sigma, same units
  bool alarm = false;
  std::string alarm_message;
  int windows = 0;  // windows fused so far
  int steps = 0;
  // The mount the BEV was made with (selfcal_applied_*), when the run
  // applied the estimate.
  std::optional<MountVector> applied;
  // The mount the lines were read under (selfcal_observed_*), when recorded.
  std::optional<MountVector> observed;
};

// The selfcal_* fields of every keyframe line of a health.jsonl
// (docs/self_calibration.md), in file order. Errors name the file, the line
// and the field; a file without any selfcal_* field is an error that says
// the run was not self-calibrated.
core::Result<std::vector<SelfCalibrationSample>> ReadSelfCalibrationHistory(
    const std::filesystem::path& health_jsonl);

// The estimate's errors against a piecewise-constant truth (the record in
// force at each sample's stamp), over the samples from `from_s` on that
// have at least one window fused.
struct SelfCalibrationErrors {
  int samples = 0;
  MountVector max_abs = MountVector::Zero();
  MountVector rms = MountVector::Zero();
  MountVector within_3_sigma = MountVector::Zero();  // fraction of the samples
};
SelfCalibrationErrors CompareWithTruth(const std::vector<SelfCalibrationSample>& history,
                                       const std::vector<core::CameraExtrinsicsRecord>& truth,
                                       double from_s = -1e300);

// One self-contained HTML page: a panel per component (degrees, millimetres)
// with the estimate, its 3-sigma band, the mount the BEV was made with (when
// the run applied the estimate), the truth when given (labelled as the
// simulation's), the commissioned value (the samples before the first window
// hold it), and a red mark at each sample where the alarm is raised; the
// alarm messages listed below.
std::string SelfCalibrationHistoryHtml(const std::vector<SelfCalibrationSample>& history,
                                       const std::vector<core::CameraExtrinsicsRecord>* truth,
                                       const std::string& title);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_SELF_CALIBRATION_HISTORY_H_
