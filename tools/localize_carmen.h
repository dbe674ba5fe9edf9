// `groundline localize --carmen LOG`: 2D LiDAR + odometry SLAM on a CARMEN log
// (localization/lidar/lidar_slam.h), with the relation metric of Kuemmerle et
// al. 2009 when --relations is given.
#ifndef GROUNDLINE_TOOLS_LOCALIZE_CARMEN_H_
#define GROUNDLINE_TOOLS_LOCALIZE_CARMEN_H_

#include <string>

namespace groundline::tools {

struct LocalizeCarmenFlags {
  std::string log_path;
  std::string relations_path;  // empty: no evaluation
  std::string out_dir;
};

// Prints "groundline localize: MESSAGE" on stderr; returns 1, the exit code
// of a data failure.
int LocalizeFail(const std::string& message);

// Returns the exit code: 0 ok, 1 data failure.
int RunLocalizeCarmen(const LocalizeCarmenFlags& flags);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LOCALIZE_CARMEN_H_
