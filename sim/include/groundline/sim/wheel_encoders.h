// Wheel-encoder simulator for a differential drive: the inverse of
// localization::IncrementFromWheels. Given the true path of base_link sampled
// at the encoder rate, it produces the per-wheel angle increments a real AGV
// reports, with the errors real encoders have:
//
// - Radius scale error: each wheel's effective radius is
//   r * (1 + e_wheel), e_wheel ~ N(0, radius_scale_stddev^2), drawn once per
//   run (tyre wear, load, manufacturing). Odometry that assumes r then sees
//   each wheel's travel scaled by 1 / (1 + e_wheel): a systematic error.
// - Random travel error per reading, growing with distance: each wheel's
//   travel d gets N(0, wheel_variance_m2_per_m * |d|) added (floor texture,
//   tyre deformation); independent across wheels and readings.
// - Slip events: a Poisson process with slip_rate_per_m events per metre of
//   path (mean of the two wheels' travel). An event adds to one random wheel a
//   spurious travel of random sign and magnitude uniform in
//   [0.5, 1.5] * slip_mean_m that the vehicle did not make (the wheel spun or
//   skidded). Events are reported so tests can find them.
// - Quantization: the encoder counts whole ticks (ticks_per_revolution per
//   turn of the wheel). The simulator keeps the continuous wheel angle and
//   reports differences of floor(angle / tick), so the quantization error of
//   the accumulated angle stays below one tick instead of drifting.
//
// Each error source draws from its own std::mt19937_64 stream derived from
// `seed`, so switching one source on or off leaves the draws of the others
// unchanged (a run with slips differs from the same run without them only by
// the slips).
//
// The truth must be feasible for a differential drive: between consecutive
// poses base_link moves on an arc (Log of the step has no lateral part) and
// turns by less than pi.
#ifndef GROUNDLINE_SIM_WHEEL_ENCODERS_H_
#define GROUNDLINE_SIM_WHEEL_ENCODERS_H_

#include <cstdint>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/core/trajectory.h"
#include "groundline/localization/diff_drive_odometry.h"

namespace groundline::sim {

struct WheelEncoderOptions {
  int ticks_per_revolution = 4096;
  double radius_scale_stddev = 0.0;      // dimensionless, e.g. 1e-3 = 0.1 %
  // The vehicle's true geometry against the nominal one the odometry is
  // given: each wheel's effective radius is r * scale * (1 + e_wheel) and the
  // effective track (where the tyres' contact patches carry the load) is
  // B * track_scale. 1: as nominal.
  double left_radius_scale = 1.0;
  double right_radius_scale = 1.0;
  double track_scale = 1.0;
  double wheel_variance_m2_per_m = 0.0;  // [m^2/m] of each wheel's own travel
  double slip_rate_per_m = 0.0;          // [1/m] expected events per metre of path
  double slip_mean_m = 0.05;             // [m] mean magnitude of a slip's spurious travel
  // Largest lateral motion of one truth step still taken as an arc [m].
  double max_lateral_step_m = 1e-6;
  std::uint64_t seed = 1;

  // Ok if ticks_per_revolution >= 1, radius_scale_stddev in [0, 0.1), the
  // three scales in [0.8, 1.2],
  // the variance, rate and magnitude finite and >= 0 and max_lateral_step_m
  // finite and > 0; otherwise names the field and the value.
  core::Status Validate() const;
};

// The increments over (stamp of the previous reading, stamp_s].
struct EncoderReading {
  double stamp_s = 0.0;
  localization::WheelAngleIncrement increment;
};

struct SlipEvent {
  int reading_index = 0;  // index into WheelEncoderLog::readings
  bool left_wheel = false;
  double spurious_travel_m = 0.0;  // signed, added to that wheel's travel
};

struct WheelEncoderLog {
  std::vector<EncoderReading> readings;  // one per truth pose after the first
  std::vector<SlipEvent> slips;          // sorted by reading_index
  double left_radius_scale = 1.0;        // left_radius_scale * (1 + e_left) drawn for this run
  double right_radius_scale = 1.0;
  double track_scale = 1.0;              // WheelEncoderOptions::track_scale
  double wheel_variance_m2_per_m = 0.0;  // WheelEncoderOptions::wheel_variance_m2_per_m
};

// Simulates the encoders along `truth` (T_world_base at the encoder rate)
// for a vehicle whose nominal geometry is `drive`. Both parameter structs must
// be valid (asserted). Fails, naming the pose, if stamps do not increase or a
// step is not an arc.
core::Result<WheelEncoderLog> SimulateWheelEncoders(const core::Trajectory& truth,
                                                    const localization::DiffDriveParams& drive,
                                                    const WheelEncoderOptions& options);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_WHEEL_ENCODERS_H_
