#include "groundline/sim/fleet_traffic.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <string>
#include <unordered_map>

#include "groundline/core/trajectory_association.h"
#include "options_check.h"

namespace groundline::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSamplePeriodS = 0.1;  // of the other robots' positions

// Where the other robots are when: their positions every kSamplePeriodS,
// hashed by cell, so that "when is a robot within r of p" reads a few cells.
class OccupancyIndex {
 public:
  OccupancyIndex(const std::vector<const core::Trajectory*>& others, double cell_m)
      : cell_m_(cell_m) {
    for (const core::Trajectory* other : others) {
      if (other == nullptr || other->empty()) continue;
      const double t0 = other->front().stamp_s, t1 = other->back().stamp_s;
      for (int i = 0;; ++i) {
        const double at = std::min(t0 + i * kSamplePeriodS, t1);
        const Vector2 p = core::InterpolatePose(*other, at).translation();
        cells_[Key(Cell(p.x()), Cell(p.y()))].push_back({at, p});
        if (at >= t1) break;
      }
    }
  }

  // Stamps (sorted) at which a robot is within radius_m of p.
  std::vector<double> TimesNear(const Vector2& p, double radius_m) const {
    std::vector<double> out;
    const int reach = static_cast<int>(std::ceil(radius_m / cell_m_));
    const int cx = Cell(p.x()), cy = Cell(p.y());
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        const auto it = cells_.find(Key(cx + dx, cy + dy));
        if (it == cells_.end()) continue;
        for (const Sample& s : it->second) {
          if ((s.position_m - p).squaredNorm() < radius_m * radius_m) out.push_back(s.stamp_s);
        }
      }
    }
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  struct Sample {
    double stamp_s;
    Vector2 position_m;
  };
  int Cell(double v) const { return static_cast<int>(std::floor(v / cell_m_)); }
  static std::int64_t Key(int x, int y) {
    return (static_cast<std::int64_t>(x) << 32) ^ static_cast<std::uint32_t>(y);
  }

  double cell_m_;
  std::unordered_map<std::int64_t, std::vector<Sample>> cells_;
};

struct Interval {
  double begin_s;
  double end_s;
};

// The complement, from t0 on, of the padded times another robot is near.
std::vector<Interval> SafeIntervals(const std::vector<double>& near_s, double pad_s, double t0) {
  std::vector<Interval> occupied;
  for (double t : near_s) {
    if (!occupied.empty() && t - pad_s <= occupied.back().end_s) {
      occupied.back().end_s = std::max(occupied.back().end_s, t + pad_s);
    } else {
      occupied.push_back({t - pad_s, t + pad_s});
    }
  }
  std::vector<Interval> safe;
  double from = t0;
  for (const Interval& o : occupied) {
    if (o.begin_s > from) safe.push_back({from, o.begin_s});
    from = std::max(from, o.end_s);
  }
  safe.push_back({from, kInf});
  return safe;
}

// Where a stamp falls in a sampled timeline: the sample at or before it and
// the fraction of the way to the next (clamped to the ends).
struct Bracket {
  std::size_t index;
  double fraction;
};
Bracket BracketOf(const core::Trajectory& stamps, double t) {
  const auto it =
      std::upper_bound(stamps.begin(), stamps.end(), t,
                       [](double s, const core::StampedPose& p) { return s < p.stamp_s; });
  if (it == stamps.begin()) return {0, 0.0};
  if (it == stamps.end()) return {stamps.size() - 1, 0.0};
  const auto i = static_cast<std::size_t>(std::distance(stamps.begin(), it));
  const double a = stamps[i - 1].stamp_s, b = stamps[i].stamp_s;
  return {i - 1, b > a ? (t - a) / (b - a) : 0.0};
}

// Linear interpolation of per-sample values at a stamp (clamped).
double ValueAt(const core::Trajectory& stamps, const std::vector<double>& values, double t) {
  const Bracket at = BracketOf(stamps, t);
  if (at.fraction == 0.0) return values[at.index];
  return values[at.index] + at.fraction * (values[at.index + 1] - values[at.index]);
}

// The planned stamp at which the route reaches arc length s (the first, at
// a standstill).
double StampAtArc(const core::Trajectory& planned, const std::vector<double>& arc, double s) {
  const auto it = std::lower_bound(arc.begin(), arc.end(), s);
  if (it == arc.begin()) return planned.front().stamp_s;
  if (it == arc.end()) return planned.back().stamp_s;
  const auto i = static_cast<std::size_t>(std::distance(arc.begin(), it));
  const double f = arc[i] > arc[i - 1] ? (s - arc[i - 1]) / (arc[i] - arc[i - 1]) : 1.0;
  return planned[i - 1].stamp_s + f * (planned[i].stamp_s - planned[i - 1].stamp_s);
}

// The planned pose at a stamp, on the arc between the bracketing samples
// (SE(2) geodesic): the retimed route stops and starts between samples, and
// a pose off that arc would move the differential drive sideways.
core::SE2 PlannedPoseAt(const core::Trajectory& planned, double t) {
  const Bracket at = BracketOf(planned, t);
  if (at.fraction == 0.0) return planned[at.index].pose;
  return core::InterpolateSE2(planned[at.index].pose, planned[at.index + 1].pose, at.fraction);
}

struct Wait {
  double stamp_s;    // planned stamp of the station
  double arc_m;      // its arc length
  double release_s;  // leave it then
};

// Steps 1-2 of the file comment: the stations at which the route must wait
// and until when.
core::Result<std::vector<Wait>> Schedule(const core::Trajectory& planned,
                                         const std::vector<double>& arc,
                                         const std::vector<double>& speeds,
                                         const OccupancyIndex& index,
                                         const TrafficOptions& options) {
  const double t0 = planned.front().stamp_s;
  const double arc_end = arc.back();
  const int n = std::max(2, static_cast<int>(std::ceil(arc_end / options.station_spacing_m)) + 1);
  std::vector<double> stamp(static_cast<std::size_t>(n));
  std::vector<std::vector<Interval>> safe(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double s = std::min(k * options.station_spacing_m, arc_end);
    stamp[k] = StampAtArc(planned, arc, s);
    const Vector2 p = core::InterpolatePose(planned, stamp[k]).translation();
    safe[k] = SafeIntervals(index.TimesNear(p, options.separation_m), options.pad_s, t0);
  }
  if (safe[0].front().begin_s > t0) {
    return core::Status::Error("traffic: another robot passes the route's start within " +
                               std::to_string(options.pad_s) + " s of it");
  }
  // Earliest arrival per (station, safe interval), and where it came from.
  std::vector<std::vector<double>> arrival(static_cast<std::size_t>(n));
  std::vector<std::vector<int>> from(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    arrival[k].assign(safe[k].size(), kInf);
    from[k].assign(safe[k].size(), -1);
  }
  arrival[0][0] = t0;
  for (int k = 0; k + 1 < n; ++k) {
    const double travel_s = stamp[k + 1] - stamp[k];
    // A stop here and a start again cost this much more than driving on.
    const double v = ValueAt(planned, speeds, stamp[k]);
    const double stop_start_s =
        v / (2.0 * options.max_brake_mps2) + v / (2.0 * options.max_accel_mps2);
    for (std::size_t i = 0; i < safe[k].size(); ++i) {
      const double a = arrival[k][i];
      if (!std::isfinite(a)) continue;
      for (std::size_t j = 0; j < safe[k + 1].size(); ++j) {
        const Interval& next = safe[k + 1][j];
        double at = a + travel_s;  // drive on
        if (at < next.begin_s) {   // wait here for the next station's interval
          const double leave = next.begin_s - travel_s - stop_start_s;
          at = std::max(leave, a) + travel_s + stop_start_s;
          if (std::max(leave, a) >= safe[k][i].end_s) continue;
        }
        if (at >= next.end_s) continue;
        if (at < arrival[k + 1][j]) {
          arrival[k + 1][j] = at;
          from[k + 1][j] = static_cast<int>(i);
        }
      }
    }
  }
  const auto best = std::min_element(arrival[n - 1].begin(), arrival[n - 1].end());
  if (!std::isfinite(*best) || *best - stamp[n - 1] > options.max_total_wait_s) {
    return core::Status::Error("traffic: no schedule past the robots before it within " +
                               std::to_string(options.max_total_wait_s) +
                               " s of waiting: their routes block each other; try another seed");
  }
  // Back along the chosen intervals: the arrival at each station.
  std::vector<double> at(static_cast<std::size_t>(n));
  int interval = static_cast<int>(std::distance(arrival[n - 1].begin(), best));
  for (int k = n - 1; k >= 0; --k) {
    at[k] = arrival[k][static_cast<std::size_t>(interval)];
    interval = from[k][static_cast<std::size_t>(interval)];
  }
  std::vector<Wait> waits;
  for (int k = 0; k + 1 < n; ++k) {
    const double travel_s = stamp[k + 1] - stamp[k];
    if (at[k + 1] - at[k] > travel_s + 1e-6) {
      const double v = ValueAt(planned, speeds, stamp[k]);
      const double start_s = v / (2.0 * options.max_accel_mps2);
      waits.push_back({stamp[k], std::min(k * options.station_spacing_m, arc_end),
                       at[k + 1] - travel_s - start_s});
    }
  }
  return waits;
}

}  // namespace

core::Status TrafficOptions::Validate() const {
  constexpr const char* kOwner = "TrafficOptions";
  return internal::FirstError({
      internal::CheckRange(kOwner, "separation_m", separation_m, 0.1, 50.0),
      internal::CheckRange(kOwner, "station_spacing_m", station_spacing_m, 0.01, 5.0),
      internal::CheckRange(kOwner, "pad_s", pad_s, 0.0, 60.0),
      internal::CheckRange(kOwner, "max_accel_mps2", max_accel_mps2, 0.01, 10.0),
      internal::CheckRange(kOwner, "max_brake_mps2", max_brake_mps2, 0.01, 10.0),
      internal::CheckRange(kOwner, "max_total_wait_s", max_total_wait_s, 0.0, 1e6),
  });
}

core::Result<Route> YieldToOthers(const Route& route,
                                  const std::vector<const core::Trajectory*>& others,
                                  const TrafficOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  const core::Trajectory& planned = route.T_map_base;
  if (planned.size() < 2) return core::Status::Error("a route to retime needs two samples");
  const double dt = planned[1].stamp_s - planned[0].stamp_s;
  const double tau0 = planned.front().stamp_s, tau_end = planned.back().stamp_s;
  std::vector<double> arc(planned.size(), 0.0);
  for (std::size_t i = 1; i < planned.size(); ++i) {
    arc[i] =
        arc[i - 1] + (planned[i].pose.translation() - planned[i - 1].pose.translation()).norm();
  }
  const bool has_rates =
      route.speed_mps.size() == planned.size() && route.yaw_rate_radps.size() == planned.size();
  std::vector<double> speeds = route.speed_mps;
  if (!has_rates) {  // from the poses
    speeds.assign(planned.size(), 0.0);
    for (std::size_t i = 1; i < planned.size(); ++i) speeds[i] = (arc[i] - arc[i - 1]) / dt;
  }
  const OccupancyIndex index(others, options.separation_m);
  core::Result<std::vector<Wait>> waits = Schedule(planned, arc, speeds, index, options);
  if (!waits.ok()) return waits.status();

  // Step 3: follow the planned timeline at a rate in [0, 1], stopping at
  // each wait's station until its release.
  Route out = route;
  out.T_map_base.clear();
  out.speed_mps.clear();
  out.yaw_rate_radps.clear();
  double tau = tau0, rate = 1.0, speed_mps = ValueAt(planned, speeds, tau0);
  std::size_t next = 0;  // the next wait
  for (std::size_t i = 0;; ++i) {
    const double t = tau0 + static_cast<double>(i) * dt;
    const double nominal_mps = ValueAt(planned, speeds, tau);
    out.T_map_base.push_back({t, PlannedPoseAt(planned, tau), std::nullopt});
    out.speed_mps.push_back(rate * nominal_mps);
    out.yaw_rate_radps.push_back(has_rates ? rate * ValueAt(planned, route.yaw_rate_radps, tau)
                                           : 0.0);
    if (tau >= tau_end) break;
    // A wait whose release has come is over, whether the vehicle reached its
    // station or is still on its way (late: it drives on).
    while (next < waits->size() && t >= (*waits)[next].release_s) ++next;
    double allowed_mps = kInf;
    double stop_tau = tau_end;
    if (next < waits->size()) {
      const Wait& w = (*waits)[next];
      stop_tau = w.stamp_s;
      const double to_go_m = w.arc_m - ValueAt(planned, arc, tau);
      allowed_mps = std::sqrt(2.0 * options.max_brake_mps2 * std::max(0.0, to_go_m));
    }
    // The speed follows min(planned, stopping curve): up at the route's
    // acceleration, down at up to twice the braking (the curve itself is
    // drawn at max_brake_mps2, so a step's lag is caught up).
    const double target_mps = std::min(nominal_mps, allowed_mps);
    if (rate >= 1.0 && target_mps >= nominal_mps) {
      speed_mps = nominal_mps;  // on the plan and nothing ahead: stay on it
    } else if (target_mps > speed_mps) {
      speed_mps = std::min(target_mps, speed_mps + options.max_accel_mps2 * dt);
    } else {
      speed_mps = std::max(target_mps, speed_mps - 2.0 * options.max_brake_mps2 * dt);
    }
    // Where the plan itself starts or stops (nominal near 0) it is followed.
    rate = nominal_mps > 0.05 ? std::min(1.0, speed_mps / nominal_mps) : 1.0;
    tau = std::min({tau + rate * dt, tau_end, std::max(tau, stop_tau)});
    if (tau_end - tau < 1e-6 * dt) tau = tau_end;  // not a sample late by rounding
    if (tau >= stop_tau && next < waits->size())
      rate = 0.0, speed_mps = 0.0;  // at the station: hold
    if (t - tau > options.max_total_wait_s + 60.0) {
      return core::Status::Error("traffic: the retimed route fell behind its schedule");
    }
  }
  out.duration_s = out.T_map_base.back().stamp_s - out.T_map_base.front().stamp_s;
  return out;
}

Separation MinimumSeparation(const core::Trajectory& a, const core::Trajectory& b) {
  Separation out{kInf, 0.0};
  if (b.empty()) return out;
  for (const core::StampedPose& p : a) {
    if (p.stamp_s < b.front().stamp_s || p.stamp_s > b.back().stamp_s) continue;
    const double d =
        (p.pose.translation() - core::InterpolatePose(b, p.stamp_s).translation()).norm();
    if (d < out.distance_m) out = {d, p.stamp_s};
  }
  return out;
}

}  // namespace groundline::sim
