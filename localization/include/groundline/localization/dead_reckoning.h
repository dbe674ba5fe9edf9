// Dead reckoning over a recorded wheel-encoder stream: the odometry-only
// baseline of every accuracy table, and the prediction the factor graph
// starts from.
//
// The pose at reading k is T_map_base(k) = T_map_base(0) * T_odom_base(k),
// with T_odom_base accumulated by OdometryIntegrator and its covariance
// propagated to first order (right perturbation, (x, y, yaw)); the initial
// pose's covariance is added at the start. Keyframes are marked with
// KeyframeSelector on the motion since the previous keyframe.
//
// Pure function of its inputs; thread-safe.
#ifndef GROUNDLINE_LOCALIZATION_DEAD_RECKONING_H_
#define GROUNDLINE_LOCALIZATION_DEAD_RECKONING_H_

#include <vector>

#include "groundline/core/dataset_records.h"
#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/localization/diff_drive_odometry.h"
#include "groundline/localization/keyframe_selector.h"

namespace groundline::localization {

struct DeadReckoningOptions {
  DiffDriveParams drive;
  OdometryNoiseParams noise;
  KeyframeSelector::Options keyframes;

  core::Status Validate() const;
};

struct DeadReckoningResult {
  // One pose per encoder reading (after applying it), with covariance;
  // the first entry is the initial pose at its own stamp.
  core::Trajectory odometry_rate;
  // The subset of odometry_rate where a keyframe was taken (first pose included).
  core::Trajectory keyframes;
  double path_length_m = 0.0;
};

// `initial` is T_map_base at initial.stamp_s (its covariance, if any, seeds
// the propagation). Readings must be sorted by strictly increasing stamp and
// start after initial.stamp_s; readings at or before it are skipped (the
// reading that covers the interval ending at the initial stamp is not applied).
// Errors: invalid options, unsorted or non-finite readings (naming the index).
core::Result<DeadReckoningResult> DeadReckon(const std::vector<core::WheelEncoderReading>& readings,
                                             const core::StampedPose& initial,
                                             const DeadReckoningOptions& options);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_DEAD_RECKONING_H_
