#include "groundline/sim/wheel_encoders.h"

#include <array>
#include <cassert>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <utility>

namespace groundline::sim {
namespace {

enum Wheel { kLeft = 0, kRight = 1 };

// One independent random stream per error source.
enum Stream : std::uint32_t { kScaleStream = 0, kNoiseStream = 1, kSlipStream = 2 };

std::mt19937_64 MakeStream(std::uint64_t seed, Stream stream) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(stream)};
  return std::mt19937_64(seq);
}

core::Status FieldError(const std::string& field, const std::string& expected, double value) {
  std::ostringstream out;
  out << "WheelEncoderOptions." << field << ": expected " << expected << ", got " << value;
  return core::Status::Error(out.str());
}

bool FiniteNonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

core::Status WheelEncoderOptions::Validate() const {
  if (ticks_per_revolution < 1) {
    return FieldError("ticks_per_revolution", "an integer >= 1", ticks_per_revolution);
  }
  if (!(FiniteNonNegative(radius_scale_stddev) && radius_scale_stddev < 0.1)) {
    return FieldError("radius_scale_stddev", "a value in [0, 0.1)", radius_scale_stddev);
  }
  for (const auto& [name, scale] : {std::pair{"left_radius_scale", left_radius_scale},
                                    std::pair{"right_radius_scale", right_radius_scale},
                                    std::pair{"track_scale", track_scale}}) {
    if (!(std::isfinite(scale) && scale >= 0.8 && scale <= 1.2)) {
      return FieldError(name, "a value in [0.8, 1.2]", scale);
    }
  }
  if (!FiniteNonNegative(wheel_variance_m2_per_m)) {
    return FieldError("wheel_variance_m2_per_m", "a finite value >= 0 [m^2/m]",
                      wheel_variance_m2_per_m);
  }
  if (!FiniteNonNegative(slip_rate_per_m)) {
    return FieldError("slip_rate_per_m", "a finite value >= 0 [1/m]", slip_rate_per_m);
  }
  if (!FiniteNonNegative(slip_mean_m)) {
    return FieldError("slip_mean_m", "a finite value >= 0 [m]", slip_mean_m);
  }
  if (!(std::isfinite(max_lateral_step_m) && max_lateral_step_m > 0.0)) {
    return FieldError("max_lateral_step_m", "a finite value > 0 [m]", max_lateral_step_m);
  }
  return core::Status::Ok();
}

core::Result<WheelEncoderLog> SimulateWheelEncoders(const core::Trajectory& truth,
                                                    const localization::DiffDriveParams& drive,
                                                    const WheelEncoderOptions& options) {
  assert(drive.Validate().ok());
  assert(options.Validate().ok());
  std::mt19937_64 scale_rng = MakeStream(options.seed, kScaleStream);
  std::mt19937_64 noise_rng = MakeStream(options.seed, kNoiseStream);
  std::mt19937_64 slip_rng = MakeStream(options.seed, kSlipStream);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  WheelEncoderLog log;
  log.left_radius_scale =
      options.left_radius_scale * (1.0 + options.radius_scale_stddev * normal(scale_rng));
  log.right_radius_scale =
      options.right_radius_scale * (1.0 + options.radius_scale_stddev * normal(scale_rng));
  log.track_scale = options.track_scale;
  log.wheel_variance_m2_per_m = options.wheel_variance_m2_per_m;
  const double track_m = drive.track_m * options.track_scale;
  const std::array<double, 2> radius_m = {drive.wheel_radius_m * log.left_radius_scale,
                                          drive.wheel_radius_m * log.right_radius_scale};
  const double ticks_per_rad = options.ticks_per_revolution / (2.0 * std::numbers::pi);

  std::array<double, 2> angle_rad = {0.0, 0.0};  // continuous wheel angle since the start
  std::array<double, 2> ticks = {0.0, 0.0};      // whole ticks counted so far
  for (size_t k = 1; k < truth.size(); ++k) {
    if (!(truth[k].stamp_s > truth[k - 1].stamp_s)) {
      std::ostringstream out;
      out << "truth trajectory pose " << k << ": field 'stamp_s': expected > "
          << truth[k - 1].stamp_s << " (strictly increasing), got " << truth[k].stamp_s;
      return core::Status::Error(out.str());
    }
    const core::Vector3 step = truth[k - 1].pose.Between(truth[k].pose).Log();
    if (std::abs(step.y()) > options.max_lateral_step_m) {
      std::ostringstream out;
      out << "truth trajectory pose " << k << " (stamp " << truth[k].stamp_s << " s): moves "
          << step.y() << " m sideways in one step; a differential drive "
          << "follows arcs (max_lateral_step_m = " << options.max_lateral_step_m << ")";
      return core::Status::Error(out.str());
    }
    const double ds = step.x();
    const double half_turn_m = 0.5 * track_m * step.z();
    std::array<double, 2> travel_m = {ds - half_turn_m, ds + half_turn_m};
    for (double& d : travel_m) {
      d += std::sqrt(options.wheel_variance_m2_per_m * std::abs(d)) * normal(noise_rng);
    }

    const double path_m = 0.5 * (std::abs(travel_m[kLeft]) + std::abs(travel_m[kRight]));
    if (uniform(slip_rng) < -std::expm1(-options.slip_rate_per_m * path_m)) {
      SlipEvent slip;
      slip.reading_index = static_cast<int>(k - 1);
      slip.left_wheel = uniform(slip_rng) < 0.5;
      const double sign = uniform(slip_rng) < 0.5 ? -1.0 : 1.0;
      slip.spurious_travel_m = sign * options.slip_mean_m * (0.5 + uniform(slip_rng));
      travel_m[slip.left_wheel ? kLeft : kRight] += slip.spurious_travel_m;
      log.slips.push_back(slip);
    }

    EncoderReading reading;
    reading.stamp_s = truth[k].stamp_s;
    std::array<double, 2> increment_rad{};
    for (int w : {kLeft, kRight}) {
      angle_rad[w] += travel_m[w] / radius_m[w];
      const double counted = std::floor(angle_rad[w] * ticks_per_rad);
      increment_rad[w] = (counted - ticks[w]) / ticks_per_rad;
      ticks[w] = counted;
    }
    reading.increment = {increment_rad[kLeft], increment_rad[kRight]};
    log.readings.push_back(reading);
  }
  return log;
}

}  // namespace groundline::sim
