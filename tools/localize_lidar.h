// The planar LiDAR in dataset localization:
// - `groundline localize --mode lidar`: LiDAR + wheel odometry only, the scan
//   odometry front end (localization/lidar/scan_odometry.h) read out at
//   odometry keyframes (0.20 m / 5 deg);
// - `--mode lines --lidar`: LidarKeyframeSource gives the floor-line
//   smoother one scan-match RelativePoseMeasurement per keyframe.
// Both add the degeneracy health per keyframe (degenerate flag, scaled
// eigenvalues, weakest direction) and, on simulated datasets, the ground-truth
// region of the keyframe (sim/zone_regions.h) with the detector's hit rates
// per region in summary.json.
#ifndef GROUNDLINE_TOOLS_LOCALIZE_LIDAR_H_
#define GROUNDLINE_TOOLS_LOCALIZE_LIDAR_H_

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "groundline/core/dataset.h"
#include "groundline/localization/lidar/scan_odometry.h"
#include "groundline/sim/zone_regions.h"
#include "localize_lines.h"

namespace groundline::tools {

// Deep in an aisle / corridor: farther than this from its ends (zone_regions.h).
inline constexpr double kRegionEndMarginM = 5.0;

class LidarKeyframeSource {
 public:
  // dataset: read with its wheel encoders (scans need not be loaded: they
  // are streamed from its lidar_scans file); start: the odometry's initial
  // T_map_base. Errors: no LiDAR or no encoders in the dataset, unreadable scans.
  static core::Result<std::unique_ptr<LidarKeyframeSource>> Open(const std::filesystem::path& dir,
                                                                 const core::Dataset& dataset,
                                                                 const core::StampedPose& start);
  ~LidarKeyframeSource();

  // Feeds the scans up to stamp_s and reads out a keyframe there
  // (T_odom_base is in the map frame of `start`). Errors: a bad scan line.
  core::Result<localization::lidar::ScanOdometryKeyframe> KeyframeAt(double stamp_s);
  // The odometry pose at stamp_s (interpolated between encoder readings).
  core::SE2 OdometryAt(double stamp_s) const;
  // After KeyframeAt(stamp_s): the scan nearest stamp_s (the last one fed or
  // the next one read ahead), or nullptr before the first scan.
  const core::LaserScan* ScanNearest(double stamp_s) const;
  const core::SE2& T_base_lidar() const;

  // Adds the degeneracy fields (and the ground-truth region) to a health line
  // and counts them for Summary().
  void AddHealth(const localization::lidar::ScanOdometryKeyframe& keyframe,
                 nlohmann::ordered_json* line);
  // Scans, matches and the detector's flagged fraction per region.
  nlohmann::ordered_json Summary() const;

 private:
  struct Impl;
  explicit LidarKeyframeSource(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// `--mode lidar`. Exit code: 0 ok, 1 data failure.
int RunLocalizeLidar(const LocalizeLinesFlags& flags);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LOCALIZE_LIDAR_H_
