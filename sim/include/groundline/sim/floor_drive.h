// A simulated drive for localization tests and benchmarks without images:
// replays a ground-truth trajectory (e.g. a sim::Route loop, repeated `loops`
// times) as noisy wheel-odometry increments, selects keyframes from the
// integrated odometry (localization::KeyframeSelector) and gives the floor
// observations at each keyframe's true pose (FloorObservationSimulator).
//
// Odometry error per step of the trajectory: the true arc (ds, dtheta) is
// scaled by (1 + distance_scale_error) and (1 + rotation_scale_error) (a
// wheel-radius and a track-width calibration error: systematic drift) and
// perturbed by Gaussian noise of localization::IncrementCovariance; the
// increment's covariance is that of the noise model (the scale error is
// not in it, as on a real vehicle).
//
// Deterministic for a seed; not thread-safe.
#ifndef GROUNDLINE_SIM_FLOOR_DRIVE_H_
#define GROUNDLINE_SIM_FLOOR_DRIVE_H_

#include <functional>
#include <random>

#include "groundline/core/trajectory.h"
#include "groundline/localization/diff_drive_odometry.h"
#include "groundline/localization/keyframe_selector.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/sim/floor_line_observations.h"

namespace groundline::sim {

struct FloorDriveOptions {
  double distance_scale_error = 0.002;
  double rotation_scale_error = 0.002;
  // The variance rates of SimRunOptions' encoders (1e-5 m^2/m per wheel),
  // used both to draw the noise and as the increments' stated covariance.
  localization::OdometryNoiseParams noise =
      localization::OdometryNoiseFromWheelVariance(1e-5, 0.760, 1e-6);
  localization::KeyframeSelector::Options keyframes;
  FloorObservationOptions observations;
  int loops = 1;
  std::uint64_t seed = 1;
};

struct DriveKeyframe {
  double stamp_s = 0.0;
  core::SE2 T_map_base_true;
  localization::RelativeMotion motion;  // since the previous keyframe
  localization::FloorObservations observations;
};

class FloorDrive {
 public:
  // trajectory: >= 2 poses with increasing stamps (asserted).
  FloorDrive(const core::FloorMap& map, core::Trajectory trajectory,
             const FloorDriveOptions& options);

  // The start: the first true pose and its stamp.
  const core::StampedPose& Start() const { return trajectory_.front(); }

  // Advances to the next keyframe; false at the end of the last loop.
  // on_step, if given, sees every odometry step (stamp, motion since the
  // last keyframe) for odometry-rate outputs.
  bool Next(DriveKeyframe* keyframe,
            const std::function<void(double, const localization::RelativeMotion&)>& on_step = {});

 private:
  FloorDriveOptions options_;
  core::Trajectory trajectory_;
  FloorObservationSimulator observer_;
  localization::OdometryIntegrator integrator_;
  localization::KeyframeSelector selector_;
  std::mt19937_64 rng_;
  size_t index_ = 0;  // current sample within the loop
  int loop_ = 0;
  double loop_duration_s_ = 0.0;
};

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_FLOOR_DRIVE_H_
