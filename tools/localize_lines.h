// `groundline localize --mode lines|mapping`: the floor-line factor graph on a
// dataset: camera frames -> BEV -> lines (perception/line_extractor.h) ->
// the sliding-window smoother (localization/sliding_window_smoother.h) with
// wheel odometry between keyframes.
#ifndef GROUNDLINE_TOOLS_LOCALIZE_LINES_H_
#define GROUNDLINE_TOOLS_LOCALIZE_LINES_H_

#include <string>
#include <vector>

namespace groundline::tools {

struct LocalizeLinesFlags {
  std::string dataset_dir;
  std::string out_dir;
  bool mapping = false;              // build the atlas instead of localizing on one
  std::string atlas_path;            // localization: the atlas (default: the dataset's floor map)
  std::string atlas_out_path;        // mapping: where to write it (default OUT/atlas.json)
  std::vector<double> initial_pose;  // x_m y_m yaw_deg
  double window_s = 120.0;
  bool lidar = false;  // lines: add the LiDAR scan-match factor (localize_lidar.h)
};

// Exit code: 0 ok, 1 data failure (named on stderr).
int RunLocalizeLines(const LocalizeLinesFlags& flags);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LOCALIZE_LINES_H_
