// The camera mount checked, and its pitch and roll corrected, from floor
// markings that are parallel (or perpendicular) in still images: each image
// is mapped to the bird's-eye view under the start mount and its lines are
// extracted; calibration::SolveMountFromParallels finds the pitch and roll
// that make them parallel; the images are mapped and extracted again under
// the solved mount and solved from again until the solution stays put (the
// step halved back where the new extraction loses the lines), and the angles
// between the lines are measured on the last extraction.
// The measured angles after are the check: they come from a new extraction,
// not from the solver's own remapped segments.
//
// `groundline calibrate parallels` runs it on an image folder
// (docs/self_calibration.md).
#ifndef GROUNDLINE_PERCEPTION_MOUNT_PARALLEL_CHECK_H_
#define GROUNDLINE_PERCEPTION_MOUNT_PARALLEL_CHECK_H_

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/mount_from_parallels.h"
#include "groundline/core/status.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/line_extractor.h"

namespace groundline::perception {

struct MountParallelCheckOptions {
  BevRemap::Options bev = BevRemap::Options::ForLineExtraction();
  LineExtractorOptions extractor;
  calibration::MountFromParallelsOptions solve;
  // Extract, solve, extract again under the solution ..: at most this many
  // solves.
  int extraction_rounds = 6;
  // Where the extraction under a solution shows no pair, the step from the
  // mount it was solved from is halved at most this many times.
  int max_step_halvings = 3;

  // The preset for a camera `height_m` above the floor: the BEV grid of
  // `ForLineExtraction` (0.6-2.4 m ahead, +-1 m, 1 cm cells, for the
  // reference camera 0.58 m high) and the extractor's least line length and
  // bar widths scaled by height_m / 0.58 (a camera half as high sees the same
  // view of a floor half the size: a 10 cm robot's road tape is 4-5 cm wide,
  // a bar of two edges where a warehouse's 8-70 cm bars are); bright markings
  // (tape, paint) only.
  static MountParallelCheckOptions ForHeight(double height_m);

  core::Status Validate() const;
};

struct NamedImage {
  std::string name;
  cv::Mat grey;  // CV_8UC1, the camera's full image
};

struct MountParallelCheck {
  calibration::MountFromParallels solution;  // the last solve's
  int extraction_rounds = 0;
  // The mount of the last extraction: the solved mount once the iteration
  // has settled (within 0.01 deg), else the last one whose extraction
  // showed a pair.
  calibration::CameraMount measured_mount;
  // The measured mount is the solved one (within 0.01 deg of pitch and
  // roll): the check stands only then.
  bool settled = false;
  // Measured on fresh extractions under the start and the measured mount.
  std::vector<calibration::LinePairAngle> measured_before, measured_after;
  std::vector<calibration::ParallelImage> lines_before, lines_after;
  std::vector<cv::Mat> bev_before, bev_after;  // CV_8UC1, per image
};

// Fails, naming why, when the options or mount are invalid, an image is not
// the camera's size, or no image shows a pair of lines.
core::Result<MountParallelCheck> CheckMountByParallels(const std::vector<NamedImage>& images,
                                                       const calibration::CameraModel& camera,
                                                       const calibration::CameraMount& start,
                                                       const MountParallelCheckOptions& options);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_MOUNT_PARALLEL_CHECK_H_
