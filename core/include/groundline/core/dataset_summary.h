// Figures that describe a loaded dataset at a glance (`groundline dataset
// check` prints them): extent in time, counts and measured rates per stream,
// distances travelled.
#ifndef GROUNDLINE_CORE_DATASET_SUMMARY_H_
#define GROUNDLINE_CORE_DATASET_SUMMARY_H_

#include <cstddef>

#include "groundline/core/dataset.h"

namespace groundline::core {

struct StreamSummary {
  std::size_t count = 0;
  double first_stamp_s = 0.0;  // 0 when count == 0
  double last_stamp_s = 0.0;
  // (count - 1) / (last - first): the mean rate, 0 with fewer than 2 records.
  double mean_rate_hz = 0.0;
};

struct DatasetSummary {
  // Over every loaded stream (images, encoders, scans, ground truth); 0 if none.
  double start_stamp_s = 0.0;
  double end_stamp_s = 0.0;
  double duration_s = 0.0;
  StreamSummary images;
  StreamSummary wheel_encoders;
  StreamSummary scans;
  StreamSummary ground_truth;
  // Sum of the translation steps between consecutive ground-truth poses.
  double ground_truth_distance_m = 0.0;
  // Sum over readings 2..n of |left + right| / 2 * wheel_radius_m; 0 without
  // an encoder sensor.
  double wheel_distance_m = 0.0;
  // Share of beams with a return over all scans, in [0, 1]; 0 without scans.
  double scan_return_fraction = 0.0;
  std::size_t floor_markings = 0;
};

DatasetSummary SummarizeDataset(const Dataset& dataset);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_DATASET_SUMMARY_H_
