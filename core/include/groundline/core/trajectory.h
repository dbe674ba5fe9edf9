// Planar trajectories and Kuemmerle relations: the value types shared by the
// dataset format, the log readers, the estimators and the metrics.
#ifndef GROUNDLINE_CORE_TRAJECTORY_H_
#define GROUNDLINE_CORE_TRAJECTORY_H_

#include <optional>
#include <vector>

#include "groundline/core/se2.h"

namespace groundline::core {

// A pose at a time. `pose` is T_frame_base for the trajectory's frame
// (map for estimates and ground truth, odom for dead reckoning).
struct StampedPose {
  double stamp_s = 0.0;  // seconds, in the clock of the input data
  SE2 pose;
  // Covariance of the pose in its tangent space (right perturbation,
  // (x, y, yaw) order, m^2 / rad^2), when the producer knows it.
  std::optional<Matrix3> covariance;
};

// Poses sorted by strictly increasing stamp.
using Trajectory = std::vector<StampedPose>;

// One ground-truth relation of Kuemmerle et al. 2009, "On measuring the
// accuracy of SLAM algorithms": the pose at t2 expressed in the frame of the
// pose at t1, i.e. delta = T_w_1^-1 * T_w_2.
struct Relation {
  double t1_s = 0.0;
  double t2_s = 0.0;
  SE2 delta;
};

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_TRAJECTORY_H_
