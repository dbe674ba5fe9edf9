// state.json: the pose `groundline serve` saves when it stops, from which a
// restart resumes (start.resume). The file is the service's own, but a restart
// reads whatever is on disk: a file cut by a full disk or edited by hand gets
// an error naming the file and the field, never an exception.
//
//   {"stamp_s": 1234.5, "x_m": 10.2, "y_m": -3.1, "yaw_rad": 1.57,
//    "cov": [9 numbers, row-major 3x3 over (x, y, yaw) in the pose's tangent space]}
#ifndef GROUNDLINE_SERVICE_SERVICE_STATE_H_
#define GROUNDLINE_SERVICE_SERVICE_STATE_H_

#include <filesystem>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::service {

struct SavedState {
  double stamp_s = 0.0;
  core::SE2 T_map_base;
  core::Matrix3 covariance = core::Matrix3::Identity();
};

// Every value finite; the covariance symmetric positive definite (what the
// localizer's SetInitialPose accepts).
core::Result<SavedState> ReadServiceState(const std::filesystem::path& path);
// Written atomically (temporary file, then rename).
core::Status WriteServiceState(const std::filesystem::path& path, const SavedState& state);

// The streamed outputs (trajectory.tum, trajectory_odometry_rate.tum,
// health.jsonl) a restart appends to are first cut back to their whole lines
// stamped at or before the saved state's stamp: a run killed after its last
// save leaves lines past it (which would precede the restart's own, breaking
// the time order) and perhaps a last line cut in the middle. Rewritten
// atomically; a missing file is fine. Returns the number of lines removed.
enum class StreamedFormat { kTum, kJsonLines };  // stamp: first field | "stamp_s"
core::Result<int> TrimStreamedOutput(const std::filesystem::path& path, StreamedFormat format,
                                     double stamp_s);

}  // namespace groundline::service

#endif  // GROUNDLINE_SERVICE_SERVICE_STATE_H_
