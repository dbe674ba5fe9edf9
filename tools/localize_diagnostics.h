// Per-keyframe diagnostics of `groundline localize --mode lines --diagnose`
// against the dataset's ground truth, written into health.jsonl:
// - the pose error of the keyframe estimate and of the odometry prediction it
//   started from, split along / across the true direction of travel [m] and
//   in heading [deg] (core/trajectory_metrics.h conventions);
// - the association check: each observed line associated at the prediction
//   (the smoother's rule: floor_association.h at the predicted pose and
//   covariance) against the same observation associated at the true pose
//   with a small pose covariance (kTruthSigma*). "right": both give the same
//   landmark (or duplicates of one marking); "wrong": different landmarks;
//   "unverified": used at the prediction, no landmark at the truth (an
//   extractor false positive or a marking the map lacks); "missed": a
//   landmark at the truth, none at the prediction (gated out or ambiguous).
// A debugging aid for the developer; not part of the estimate.
#ifndef GROUNDLINE_TOOLS_LOCALIZE_DIAGNOSTICS_H_
#define GROUNDLINE_TOOLS_LOCALIZE_DIAGNOSTICS_H_

#include <optional>

#include <nlohmann/json.hpp>

#include "groundline/core/trajectory.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_association.h"
#include "groundline/localization/floor_observation.h"
#include "groundline/localization/sliding_window_smoother.h"

namespace groundline::tools {

class LocalizeDiagnostics {
 public:
  // ground_truth must be non-empty and sorted; the atlas is copied.
  LocalizeDiagnostics(const core::Trajectory& ground_truth, localization::Atlas atlas,
                      const localization::AssociationOptions& association);

  // The true pose at stamp_s (interpolated; clamped at the ends).
  core::SE2 TruePose(double stamp_s) const;

  // Fields of the prediction and its association check, before AddKeyframe.
  nlohmann::ordered_json BeforeUpdate(const localization::PoseEstimate& predicted,
                                      const localization::FloorObservations& observations) const;
  // Fields of the keyframe estimate, after AddKeyframe.
  nlohmann::ordered_json AfterUpdate(const localization::PoseEstimate& estimate) const;

 private:
  nlohmann::ordered_json Errors(const localization::PoseEstimate& estimate,
                                const char* prefix) const;

  const core::Trajectory& ground_truth_;
  localization::Atlas atlas_;
  localization::AssociationOptions association_;
};

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LOCALIZE_DIAGNOSTICS_H_
