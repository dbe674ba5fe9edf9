#include "groundline/io/carmen_order.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>

namespace groundline::io {

core::Status CarmenScanOrderOptions::Validate() const {
  if (!std::isfinite(window_s) || window_s < 0.0) {
    return core::Status::Error(
        "CarmenScanOrderOptions.window_s: expected a finite value >= 0 s, got " +
        std::to_string(window_s));
  }
  return core::Status::Ok();
}

core::Result<CarmenScanOrder> OrderLaserScans(std::span<const CarmenLaserScan* const> scans,
                                              const CarmenScanOrderOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  // Held scans, earliest stamp first; equal stamps in reading order. delay_s:
  // how much newer the newest scan read before it was (0: read in order).
  struct Held {
    double stamp_s;
    std::size_t index;
    double delay_s;
    bool operator>(const Held& o) const {
      return stamp_s != o.stamp_s ? stamp_s > o.stamp_s : index > o.index;
    }
  };
  std::priority_queue<Held, std::vector<Held>, std::greater<>> held;
  CarmenScanOrder order;
  order.scans.reserve(scans.size());
  // Stamps are finite (checked below): -inf stands for "none yet".
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  double last_released_s = kNone;
  double newest_s = kNone;
  const auto drop = [&](const CarmenLaserScan& s, std::int64_t& counter) {
    ++counter;
    if (order.first_dropped_line == 0) order.first_dropped_line = s.line;
  };
  const auto release_before = [&](double before_s) {
    while (!held.empty() && held.top().stamp_s < before_s) {
      const Held h = held.top();
      held.pop();
      const CarmenLaserScan& s = *scans[h.index];
      if (s.stamp_s <= last_released_s) {
        drop(s, order.dropped_duplicate);  // equal: held scans are released in order
        continue;
      }
      if (h.delay_s > 0.0) {
        ++order.reordered;
        order.max_delay_s = std::max(order.max_delay_s, h.delay_s);
        if (order.first_reordered_line == 0 || s.line < order.first_reordered_line) {
          order.first_reordered_line = s.line;
        }
      }
      order.scans.push_back(&s);
      last_released_s = s.stamp_s;
    }
  };
  for (std::size_t i = 0; i < scans.size(); ++i) {
    if (scans[i] == nullptr) {
      return core::Status::Error("OrderLaserScans: scan " + std::to_string(i) + " is null");
    }
    const CarmenLaserScan& s = *scans[i];
    if (!std::isfinite(s.stamp_s)) {
      return core::Status::Error("OrderLaserScans: line " + std::to_string(s.line) +
                                 ": the laser's ipc_timestamp is not finite");
    }
    if (s.stamp_s <= last_released_s) {
      drop(s, s.stamp_s == last_released_s ? order.dropped_duplicate : order.dropped_late);
      continue;
    }
    held.push({s.stamp_s, i, s.stamp_s < newest_s ? newest_s - s.stamp_s : 0.0});
    newest_s = std::max(newest_s, s.stamp_s);
    release_before(newest_s - options.window_s);
  }
  release_before(std::numeric_limits<double>::infinity());
  return order;
}

}  // namespace groundline::io
