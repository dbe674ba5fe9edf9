// Example: the groundline libraries without the CLI. Reads a dataset, dead-
// reckons its wheel encoders from the first ground-truth pose, and prints the
// accuracy of the result.
//
//   build/samples/replay_odometry_example DATASET_DIR
#include <cstdio>

#include "groundline/core/dataset.h"
#include "groundline/core/trajectory_metrics.h"
#include "groundline/localization/dead_reckoning.h"

int main(int argc, char** argv) {
  using namespace groundline;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DATASET_DIR (e.g. one written by 'groundline sim')\n",
                 argv[0]);
    return 2;
  }
  core::DatasetReadOptions read;
  read.load_scans = false;
  read.load_images = false;
  const core::Result<core::Dataset> dataset = core::ReadDataset(argv[1], read);
  if (!dataset.ok()) {
    std::fprintf(stderr, "%s\n", dataset.message().c_str());
    return 1;
  }
  if (dataset->ground_truth.empty() || !dataset->manifest.wheel_encoders) {
    std::fprintf(stderr, "%s: needs wheel encoders and ground truth\n", argv[1]);
    return 1;
  }
  localization::DeadReckoningOptions options;
  options.drive.wheel_radius_m = dataset->manifest.wheel_encoders->wheel_radius_m;
  options.drive.track_m = dataset->manifest.wheel_encoders->track_m;
  core::StampedPose start = dataset->ground_truth.front();
  const core::Result<localization::DeadReckoningResult> odometry =
      localization::DeadReckon(dataset->wheel_encoders, start, options);
  if (!odometry.ok()) {
    std::fprintf(stderr, "%s\n", odometry.message().c_str());
    return 1;
  }
  const core::Result<core::TrajectoryErrorSummary> errors =
      core::ComputeTrajectoryErrors(odometry->keyframes, dataset->ground_truth);
  if (!errors.ok()) {
    std::fprintf(stderr, "%s\n", errors.message().c_str());
    return 1;
  }
  std::printf("%zu keyframes over %.1f m: ATE RMSE %.3f m, along-track RMSE %.3f m, "
              "heading RMSE %.2f deg\n",
              odometry->keyframes.size(), odometry->path_length_m, errors->ate_m.rmse,
              errors->along_rmse_m, errors->heading_rmse_deg);
  return 0;
}
