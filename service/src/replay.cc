#include "groundline/service/replay.h"

#include <chrono>
#include <opencv2/imgcodecs.hpp>
#include <thread>

namespace groundline::service {

core::Result<ReplayStats> ReplayEvents(core::DatasetStreams& streams, const ReplayOptions& options,
                                       const std::function<void(core::DatasetEvent&)>& sink) {
  using Clock = std::chrono::steady_clock;
  ReplayStats stats;
  std::optional<double> first_wheel_s;
  std::optional<double> first_paced_s;
  const Clock::time_point wall_start = Clock::now();
  core::DatasetEvent event;
  while (true) {
    if (options.stop && options.stop()) {
      stats.stopped = true;
      break;
    }
    core::Result<bool> next = streams.Next(&event);
    if (!next.ok()) return next.status();
    if (!*next) break;
    if (stats.events == 0) stats.first_stamp_s = event.stamp_s;
    ++stats.events;
    stats.last_stamp_s = event.stamp_s;
    if (event.kind == core::DatasetEvent::Kind::kWheel && !first_wheel_s) {
      first_wheel_s = event.stamp_s;
    }
    if (options.max_duration_s > 0.0 && first_wheel_s &&
        event.stamp_s > *first_wheel_s + options.max_duration_s) {
      break;
    }
    if (event.stamp_s <= options.start_after_s) continue;
    if (options.speed > 0.0) {
      if (!first_paced_s) first_paced_s = event.stamp_s;
      std::this_thread::sleep_until(
          wall_start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                           (event.stamp_s - *first_paced_s) / options.speed)));
    }
    sink(event);
  }
  return stats;
}

core::Result<ReplayStats> Replay(core::DatasetStreams& streams, localization::Localizer& localizer,
                                 const ReplayOptions& options, const ReplayCallbacks& callbacks) {
  long events = 0;
  return ReplayEvents(streams, options, [&](core::DatasetEvent& event) {
    switch (event.kind) {
      case core::DatasetEvent::Kind::kScan:
        localizer.AddScan(std::move(event.scan));
        break;
      case core::DatasetEvent::Kind::kFrame: {
        const std::filesystem::path path = event.image_path;
        localizer.AddFrame(event.stamp_s,
                           [path] { return cv::imread(path.string(), cv::IMREAD_GRAYSCALE); });
        break;
      }
      case core::DatasetEvent::Kind::kWheel: {
        const double before_s = localizer.started() ? localizer.Current().stamp_s : -1.0;
        std::optional<localization::KeyframeOutput> keyframe =
            localizer.AddWheelReading(event.wheel);
        if (keyframe && callbacks.on_keyframe) callbacks.on_keyframe(*keyframe);
        if (localizer.started() && callbacks.on_pose && localizer.Current().stamp_s != before_s) {
          callbacks.on_pose(localizer.Current());
        }
        break;
      }
    }
    if (callbacks.on_progress && ++events % 1000 == 0) callbacks.on_progress(event.stamp_s);
  });
}

}  // namespace groundline::service
