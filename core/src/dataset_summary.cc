#include "groundline/core/dataset_summary.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace groundline::core {
namespace {

template <typename Record>
StreamSummary Summarize(const std::vector<Record>& records) {
  StreamSummary s;
  s.count = records.size();
  if (records.empty()) return s;
  s.first_stamp_s = records.front().stamp_s;
  s.last_stamp_s = records.back().stamp_s;
  if (records.size() >= 2) {
    s.mean_rate_hz = static_cast<double>(records.size() - 1) / (s.last_stamp_s - s.first_stamp_s);
  }
  return s;
}

}  // namespace

DatasetSummary SummarizeDataset(const Dataset& d) {
  DatasetSummary summary;
  summary.images = Summarize(d.images);
  summary.wheel_encoders = Summarize(d.wheel_encoders);
  summary.scans = Summarize(d.scans);
  summary.ground_truth = Summarize(d.ground_truth);
  bool any = false;
  for (const StreamSummary* s :
       {&summary.images, &summary.wheel_encoders, &summary.scans, &summary.ground_truth}) {
    if (s->count == 0) continue;
    summary.start_stamp_s =
        any ? std::min(summary.start_stamp_s, s->first_stamp_s) : s->first_stamp_s;
    summary.end_stamp_s = any ? std::max(summary.end_stamp_s, s->last_stamp_s) : s->last_stamp_s;
    any = true;
  }
  summary.duration_s = summary.end_stamp_s - summary.start_stamp_s;

  for (std::size_t i = 1; i < d.ground_truth.size(); ++i) {
    summary.ground_truth_distance_m +=
        (d.ground_truth[i].pose.translation() - d.ground_truth[i - 1].pose.translation()).norm();
  }
  if (d.manifest.wheel_encoders) {
    const double radius_m = d.manifest.wheel_encoders->wheel_radius_m;
    for (std::size_t i = 1; i < d.wheel_encoders.size(); ++i) {
      const WheelEncoderReading& r = d.wheel_encoders[i];
      summary.wheel_distance_m += 0.5 * std::abs(r.left_delta_rad + r.right_delta_rad) * radius_m;
    }
  }
  std::size_t beams = 0, returns = 0;
  for (const LaserScan& scan : d.scans) {
    beams += scan.ranges_m.size();
    for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) returns += scan.IsReturn(i) ? 1 : 0;
  }
  if (beams > 0) summary.scan_return_fraction = static_cast<double>(returns) / beams;
  summary.floor_markings = d.floor_map ? d.floor_map->markings.size() : 0;
  return summary;
}

}  // namespace groundline::core
