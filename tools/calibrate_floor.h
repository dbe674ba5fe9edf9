// `groundline calibrate floor`, shared by the folder flow
// (calibrate_floor_command.cc) and the live flow (calibrate_live_floor.cc).
#ifndef GROUNDLINE_TOOLS_CALIBRATE_FLOOR_H_
#define GROUNDLINE_TOOLS_CALIBRATE_FLOOR_H_

#include <filesystem>
#include <string>

#include "groundline/calibration/camera_model.h"
#include "groundline/calibration/floor_calibration.h"
#include "groundline/calibration/tag_layout.h"

namespace groundline::tools {

struct CalibrateFloorFlags {
  std::string images;
  std::string live;  // frame source URI (io/frame_source.h)
  std::string layout;
  std::string camera;
  std::string out;
  double max_bev_error_2m_mm = 5.0;
  double max_rms_px = 0.5;
  double corner_sigma_px = 0.0;
  std::string config;             // YAML with a floor_report: mapping of thresholds
  std::string intrinsics_report;  // report.json of `calibrate intrinsics`
  bool max_bev_given = false;     // command-line thresholds override --config
  bool max_rms_given = false;
  // Live only.
  int frames_per_tag = 3;
  int max_frames = 0;       // 0: no limit
  double duration_s = 0.0;  // 0: no limit
  double timeout_s = 5.0;   // wait for one frame
  std::string save_frames;  // default OUT/frames
};

// Solves from the images of image_dir exactly as `calibrate floor --images`
// does, writes the outputs into flags.out and prints the result; the exit
// code (0 PASS, 1 FAIL or a data error).
int SolveAndReportFloor(const CalibrateFloorFlags& flags, const calibration::TagLayout& layout,
                        const calibration::CameraModel& camera,
                        const std::filesystem::path& image_dir,
                        const calibration::FloorCalibrationOptions& options);

// The live flow: frames from flags.live until every layout tag is in enough
// frames (or a limit); the kept frames are written to --save-frames (default
// OUT/frames) and solved from there by SolveAndReportFloor.
int RunCalibrateFloorLive(const CalibrateFloorFlags& flags, const calibration::TagLayout& layout,
                          const calibration::CameraModel& camera,
                          const calibration::FloorCalibrationOptions& options);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_CALIBRATE_FLOOR_H_
