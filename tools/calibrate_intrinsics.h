// `groundline calibrate intrinsics`, shared by the folder flow
// (calibrate_command.cc) and the live flow (calibrate_live_intrinsics.cc):
// the flags, the setup they turn into, and the solve-and-report step both
// end with.
#ifndef GROUNDLINE_TOOLS_CALIBRATE_INTRINSICS_H_
#define GROUNDLINE_TOOLS_CALIBRATE_INTRINSICS_H_

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "groundline/calibration/calib_target.h"
#include "groundline/calibration/calibration_report.h"
#include "groundline/calibration/intrinsic_calibration.h"

namespace groundline::tools {

struct IntrinsicsFlags {
  std::string images;
  std::string live;  // frame source URI (io/frame_source.h)
  std::string target;
  std::string model = "LENSMODEL_OPENCV8";
  std::string out_dir;
  std::string config;
  std::string targets_file;
  bool no_board_warp = false;
  bool no_outlier_rejection = false;
  // Live only.
  int min_views = 0;        // 0: the report's min_views (one rule for guidance and verdict)
  int max_views = 0;        // 0: no limit
  double duration_s = 0.0;  // 0: no limit
  double timeout_s = 5.0;   // wait for one frame
  std::string save_frames;  // directory for the kept frames, "" = none
};

struct IntrinsicsSetup {
  calibration::CalibTarget target;
  calibration::BoardGrid grid;
  calibration::IntrinsicCalibrationOptions options;
  calibration::ReportThresholds thresholds;
};

// Reads the targets file and --config, validates the options. Returns 0 and
// fills *setup, or prints the reason and returns the exit code (1 data, 2 usage).
int PrepareIntrinsics(const IntrinsicsFlags& flags, IntrinsicsSetup* setup);

// Solves, writes the outputs into --out and prints the verdict; the exit code
// (0 PASS, 1 FAIL or unusable data). live_missing: what the live guidance
// still asked for when the session stopped (each becomes a FAIL reason).
int SolveAndReportIntrinsics(const IntrinsicsFlags& flags, const IntrinsicsSetup& setup,
                             const std::vector<calibration::CalibrationView>& views,
                             std::vector<calibration::RejectedImage> rejected, cv::Size size,
                             std::vector<std::string> live_missing = {});

// The live flow: frames from flags.live until the coverage is complete (or a
// limit), then SolveAndReportIntrinsics.
int RunIntrinsicsLive(const IntrinsicsFlags& flags);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_CALIBRATE_INTRINSICS_H_
