// The localizer's outputs as JSON, one format for the replay's health.jsonl,
// the service's health stream and its HTTP endpoint (docs/localization.md,
// "health.jsonl").
#ifndef GROUNDLINE_LOCALIZATION_LOCALIZER_JSON_H_
#define GROUNDLINE_LOCALIZATION_LOCALIZER_JSON_H_

#include <nlohmann/json.hpp>

#include "groundline/localization/localizer.h"

namespace groundline::localization {

// One keyframe: "keyframe" (1-based: row 0 of the trajectory is the start),
// stamp, pose, covariance (row-major 3x3, x y yaw), mode, what the lines,
// the smoother, the LiDAR and the wall lines did, the sensors' state.
nlohmann::ordered_json KeyframeJson(const KeyframeOutput& keyframe, LocalizerMode mode);
// The LiDAR fields of a keyframe (degeneracy, information, aliasing, the
// relative measurement).
void AddLidarJson(const lidar::ScanOdometryKeyframe& keyframe, nlohmann::ordered_json* line);
// Every counter by name.
nlohmann::ordered_json CountersJson(const LocalizerCounters& counters);
// What went into a mapping run's atlas, by name (AtlasMapperReport).
nlohmann::ordered_json AtlasMapperReportJson(const AtlasMapperReport& report);
// "odometry", "lines", "lines+lidar", "mapping", "mapping+lidar", "lidar".
std::string ModeName(const LocalizerOptions& options);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_LOCALIZER_JSON_H_
