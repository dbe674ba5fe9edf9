#include "groundline/sim/mount_perturbation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "options_check.h"

namespace groundline::sim {

core::Status MountPerturbationOptions::Validate() const {
  constexpr const char* kOwner = "MountPerturbationOptions";
  if (core::Status s = internal::FirstError({
          internal::CheckRange(kOwner, "height_loss_m_per_km", height_loss_m_per_km, 0.0, 0.1),
          internal::CheckRange(kOwner, "drift_step_m", drift_step_m, 1e-6, 0.01),
      });
      !s.ok()) {
    return s;
  }
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const MountStep& m = steps[i];
    const std::string owner = std::string(kOwner) + ".steps[" + std::to_string(i) + "]";
    if (core::Status s = internal::FirstError({
            internal::CheckRange(owner.c_str(), "at_s", m.at_s, 0.0, 1e7),
            internal::CheckRange(owner.c_str(), "height_m", m.height_m, -0.5, 0.5),
            internal::CheckRange(owner.c_str(), "pitch_rad", m.pitch_rad, -0.5, 0.5),
            internal::CheckRange(owner.c_str(), "roll_rad", m.roll_rad, -0.5, 0.5),
            internal::CheckRange(owner.c_str(), "yaw_rad", m.yaw_rad, -0.5, 0.5),
            internal::CheckRange(owner.c_str(), "forward_m", m.forward_m, -0.5, 0.5),
            internal::CheckRange(owner.c_str(), "lateral_m", m.lateral_m, -0.5, 0.5),
        });
        !s.ok()) {
      return s;
    }
  }
  return core::Status::Ok();
}

calibration::CameraMount PerturbedMount(const calibration::CameraMount& nominal,
                                        const MountPerturbationOptions& options, double elapsed_s,
                                        double distance_m) {
  calibration::CameraMount m = nominal;
  for (const MountStep& step : options.steps) {
    if (elapsed_s < step.at_s) continue;
    m.height_m += step.height_m;
    m.pitch_rad += step.pitch_rad;
    m.roll_rad += step.roll_rad;
    m.yaw_rad += step.yaw_rad;
    m.forward_m += step.forward_m;
    m.lateral_m += step.lateral_m;
  }
  if (options.height_loss_m_per_km > 0.0) {
    const double loss_m = options.height_loss_m_per_km * distance_m / 1000.0;
    m.height_m -= options.drift_step_m * std::floor(loss_m / options.drift_step_m);
  }
  return m;
}

calibration::CameraMount ToMount(const core::CameraExtrinsicsRecord& r) {
  calibration::CameraMount m;
  m.height_m = r.height_m;
  m.pitch_rad = r.pitch_rad;
  m.roll_rad = r.roll_rad;
  m.yaw_rad = r.yaw_rad;
  m.forward_m = r.forward_m;
  m.lateral_m = r.lateral_m;
  return m;
}

core::CameraExtrinsicsRecord ToRecord(double stamp_s, const calibration::CameraMount& m) {
  return {stamp_s, m.height_m, m.pitch_rad, m.roll_rad, m.yaw_rad, m.forward_m, m.lateral_m};
}

core::Result<std::vector<core::CameraExtrinsicsRecord>> MountSchedule(
    const calibration::CameraMount& nominal, const MountPerturbationOptions& options,
    const core::Trajectory& T_map_base) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  std::vector<core::CameraExtrinsicsRecord> schedule;
  if (T_map_base.empty()) return schedule;
  const double t0_s = T_map_base.front().stamp_s;
  double distance_m = 0.0;
  for (std::size_t k = 0; k < T_map_base.size(); ++k) {
    if (k > 0) {
      distance_m +=
          (T_map_base[k].pose.translation() - T_map_base[k - 1].pose.translation()).norm();
    }
    const double stamp_s = T_map_base[k].stamp_s;
    const calibration::CameraMount m = PerturbedMount(nominal, options, stamp_s - t0_s, distance_m);
    const core::CameraExtrinsicsRecord r = ToRecord(stamp_s, m);
    if (!schedule.empty()) {
      const core::CameraExtrinsicsRecord& p = schedule.back();
      if (p.height_m == r.height_m && p.pitch_rad == r.pitch_rad && p.roll_rad == r.roll_rad &&
          p.yaw_rad == r.yaw_rad && p.forward_m == r.forward_m && p.lateral_m == r.lateral_m) {
        continue;
      }
    }
    if (core::Status s = m.Validate(); !s.ok()) {
      std::ostringstream message;
      message << "the perturbed camera mount at t = " << stamp_s - t0_s
              << " s is invalid (check the steps and height_loss_m_per_km): " << s.message();
      return core::Status::Error(message.str());
    }
    schedule.push_back(r);
  }
  return schedule;
}

std::size_t RecordAt(const std::vector<core::CameraExtrinsicsRecord>& schedule, double stamp_s) {
  const auto after = std::upper_bound(
      schedule.begin(), schedule.end(), stamp_s,
      [](double t, const core::CameraExtrinsicsRecord& r) { return t < r.stamp_s; });
  return after == schedule.begin() ? 0 : static_cast<std::size_t>(after - schedule.begin()) - 1;
}

}  // namespace groundline::sim
