// Replays a dataset's merged sensor streams (core/dataset_streams.h) into a
// Localizer, as fast as possible or paced to its timestamps (real time or
// N times faster). The same loop serves `groundline localize --dataset`, the
// service's replay input and the tests.
#ifndef GROUNDLINE_SERVICE_REPLAY_H_
#define GROUNDLINE_SERVICE_REPLAY_H_

#include <functional>
#include <limits>

#include "groundline/core/dataset_streams.h"
#include "groundline/core/status.h"
#include "groundline/localization/localizer.h"

namespace groundline::service {

struct ReplayOptions {
  // Stop after this many seconds of data past the first wheel reading (0: all).
  double max_duration_s = 0.0;
  // Skip the events up to this stamp (a resumed run), -inf: none.
  double start_after_s = -std::numeric_limits<double>::infinity();
  // 0: as fast as possible; 1: at the data's own pace; N: N times faster.
  double speed = 0.0;
  // Stop when this returns true (checked between events; e.g. a signal).
  std::function<bool()> stop;
};

struct ReplayCallbacks {
  std::function<void(const localization::KeyframeOutput&)> on_keyframe;
  // After every wheel reading the localizer accepted once started: the pose then.
  std::function<void(const localization::PoseEstimate&)> on_pose;
  // The data time reached [s], now and then (every 1000 events).
  std::function<void(double stamp_s)> on_progress;
};

struct ReplayStats {
  long events = 0;
  double first_stamp_s = 0.0;
  double last_stamp_s = 0.0;
  bool stopped = false;  // by ReplayOptions::stop
};

// The paced event loop alone: each event goes to `sink` at its time.
// Errors: a malformed scan line in the stream.
core::Result<ReplayStats> ReplayEvents(core::DatasetStreams& streams, const ReplayOptions& options,
                                       const std::function<void(core::DatasetEvent&)>& sink);

// Errors: a malformed scan line in the stream (the localizer's state is kept).
core::Result<ReplayStats> Replay(core::DatasetStreams& streams, localization::Localizer& localizer,
                                 const ReplayOptions& options, const ReplayCallbacks& callbacks);

}  // namespace groundline::service

#endif  // GROUNDLINE_SERVICE_REPLAY_H_
