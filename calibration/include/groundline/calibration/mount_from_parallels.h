// The camera's pitch and roll from floor lines that are parallel or
// perpendicular on the floor, in still images: no odometry, no map, no
// target. A wrong pitch makes parallel markings converge or diverge in the
// bird's-eye view (about 4.5 deg of angle between the two edges of a lane
// per degree of pitch on a low camera); a wrong roll tilts them unequally.
// The height only scales the view and the yaw turns every line alike, so
// neither is observable here: both stay as given.
//
// In each image the longest segment is the reference; every other segment
// within `parallel_tolerance_deg` of it (under the current estimate) is
// parallel to it, and within `perpendicular_tolerance_deg` of its normal
// perpendicular (a stop bar across an aisle line). One residual per segment
// against its image's reference (a spanning star: no pair's evidence counts
// twice): the sine of the angle off parallel (cosine for perpendicular),
// over its sigma from both segments' angle covariances, under a Cauchy loss.
// The first solve's loss is ten times wider (at the start mount every pair is
// many sigmas off, and a tight Cauchy would take the signal for outliers);
// then the pairing is redone under each solution, with the loss at its
// scale, until it stops changing.
//
// The estimate is the mount self-calibration's single-image check
// (mount_self_calibration.h estimates the whole mount while driving); the
// command is `groundline calibrate parallels` (docs/self_calibration.md).
#ifndef GROUNDLINE_CALIBRATION_MOUNT_FROM_PARALLELS_H_
#define GROUNDLINE_CALIBRATION_MOUNT_FROM_PARALLELS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/mount_self_calibration.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

// One image's floor segments, measured under `mount_used`.
struct ParallelImage {
  std::string name;
  CameraMount mount_used;
  std::vector<FloorSegment> segments;
};

struct MountFromParallelsOptions {
  // Pairing under the current estimate. A 3 deg pitch error turns a low
  // camera's lane edges up to ~15 deg apart, so the gate is wide.
  double parallel_tolerance_deg = 25.0;
  double perpendicular_tolerance_deg = 15.0;
  bool use_perpendicular = true;
  double min_segment_length_m = 0.0;  // shorter segments take no part
  // Added to each endpoint's distance sigma (the extractor's covariance holds
  // the ridge noise, not the marking's own waviness).
  double min_segment_sigma_m = 0.001;
  // Priors on the change from the start mount: pitch is what the lines pin;
  // the roll prior keeps a view with a single pair of lines well posed.
  double pitch_prior_sigma_deg = 10.0;
  double roll_prior_sigma_deg = 1.0;
  double loss_scale = 2.0;  // Cauchy scale, in sigmas
  int max_rounds = 5;       // pair, solve, pair again ..

  core::Status Validate() const;
};

// One segment against its image's reference: how far from parallel (or from
// perpendicular) the two are under some mount, in degrees (>= 0).
struct LinePairAngle {
  int image = 0;
  int reference = 0;  // segment indices in that image
  int other = 0;
  bool perpendicular = false;
  double off_deg = 0.0;
};

// The pairs of every image under `mount` (each image's segments remapped
// from its mount_used to `mount`, see mount_remap.h), with their angles.
std::vector<LinePairAngle> PairParallelLines(const std::vector<ParallelImage>& images,
                                             const CameraMount& mount,
                                             const MountFromParallelsOptions& options);

struct MountFromParallels {
  CameraMount mount;  // the start mount with pitch and roll solved
  // Of (pitch_rad, roll_rad), the priors included: with a single pair of
  // lines the roll's sigma is its prior's.
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  std::vector<LinePairAngle> pairs_before;  // under the start mount
  std::vector<LinePairAngle> pairs_after;   // under the solved mount
  int rounds = 0;
};

// Fails, naming why, when the options are invalid or no image has a pair.
core::Result<MountFromParallels> SolveMountFromParallels(const std::vector<ParallelImage>& images,
                                                         const CameraMount& start,
                                                         const MountFromParallelsOptions& options);

// The largest and the median off-angle of some pairs, in degrees (0 for none).
double MaxOffDeg(const std::vector<LinePairAngle>& pairs);
double MedianOffDeg(const std::vector<LinePairAngle>& pairs);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_MOUNT_FROM_PARALLELS_H_
