// The laser scans of a CARMEN log in stamp order, as a live system would
// take them from a stream whose messages arrive out of order.
//
// Some logs write scans out of order (two logging processes, a laser and an
// odometry module with their own clocks): a scan's ipc_timestamp can be below
// one written before it. A consumer that needs increasing stamps (the LiDAR
// SLAM, the relation metric) gets them from OrderLaserScans:
//   - each scan is held until a scan stamped more than window_s later has
//     been read (or the log ends), then released in stamp order, so a scan up
//     to window_s late takes its place among the others (`reordered`);
//   - a scan stamped no later than the last scan released (so more than
//     window_s late) is dropped (`dropped_late`), never moved back in time;
//   - a scan whose stamp equals that of the scan taken before it is dropped
//     (`dropped_duplicate`): two scans cannot hold the same instant.
// The ordering never looks further ahead than window_s, so the same rule
// works on a live stream with window_s of latency. A log whose scans are in
// order comes out unchanged.
//
// Thread-safety: a pure function.
#ifndef GROUNDLINE_IO_CARMEN_ORDER_H_
#define GROUNDLINE_IO_CARMEN_ORDER_H_

#include <cstdint>
#include <span>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/io/carmen.h"

namespace groundline::io {

struct CarmenScanOrderOptions {
  // How late a scan may arrive and still take its place. A second holds ten
  // to forty scans of the Radish logs' lasers and costs a live system that
  // much latency; the out-of-order scans of real logs are a few scans late.
  double window_s = 1.0;
  core::Status Validate() const;  // finite, >= 0
};

struct CarmenScanOrder {
  std::vector<const CarmenLaserScan*> scans;  // strictly increasing stamp_s
  std::int64_t reordered = 0;                 // kept, though read after a newer scan
  std::int64_t dropped_late = 0;              // more than window_s late
  std::int64_t dropped_duplicate = 0;         // the stamp of the scan taken before it
  double max_delay_s = 0.0;                   // the latest of the reordered scans
  std::int64_t first_reordered_line = 0;      // 0: none
  std::int64_t first_dropped_line = 0;        // 0: none
};

// `scans` in the order they were read (file order). Errors: invalid options,
// a null pointer or a non-finite stamp.
core::Result<CarmenScanOrder> OrderLaserScans(std::span<const CarmenLaserScan* const> scans,
                                              const CarmenScanOrderOptions& options = {});

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_CARMEN_ORDER_H_
