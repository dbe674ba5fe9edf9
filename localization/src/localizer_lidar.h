// The localizer's LiDAR stage (localizer.h): scans queued in the time order
// of the instant they describe, matched by the scan odometry once the wheel
// odometry covers that instant, read out at keyframes; and the straight
// faces of the last matched scan as wall observations. Private to the
// localization library.
#ifndef GROUNDLINE_LOCALIZATION_SRC_LOCALIZER_LIDAR_H_
#define GROUNDLINE_LOCALIZATION_SRC_LOCALIZER_LIDAR_H_

#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "groundline/core/dataset_records.h"
#include "groundline/core/trajectory.h"
#include "groundline/localization/localizer.h"

namespace groundline::localization::internal {

class LidarStage {
 public:
  LidarStage(const LidarSetup& setup, const LocalizerOptions& options);

  // The odometry frame's origin: scans describing times up to stamp_s are
  // not matched (the estimate starts there).
  void Start(double stamp_s, const core::SE2& T_odom_base);
  // Checks and queues a scan. Returns false (and counts) when dropped.
  bool AddScan(core::LaserScan scan, LocalizerCounters* counters);
  // The odometry pose at a reading's time (strictly increasing); matches
  // the queued scans it now covers.
  void AddOdometry(double stamp_s, const core::SE2& T_odom_base, LocalizerCounters* counters);
  // A keyframe at stamp_s (the odometry must cover it); renews the scan
  // odometry after LocalizerOptions::lidar_local_map_scans (counted).
  lidar::ScanOdometryKeyframe Keyframe(double stamp_s, LocalizerCounters* counters);
  // A re-initialization (Localizer::SetInitialPose after the start): a fresh
  // scan odometry continues from T_map_base at stamp_s (the odometry must
  // cover it), so that the old local map does not pull the estimate back.
  void Renew(double stamp_s, const core::SE2& T_map_base);
  // Also given every deskewed scan matched, with the instant it describes and
  // the odometry there (T_odom_base as given to AddOdometry): the mapper's
  // LiDAR SLAM.
  using ScanSink = std::function<void(double, const core::SE2&, const lidar::ScanPoints&)>;
  void SetScanSink(ScanSink sink) { sink_ = std::move(sink); }
  // The straight faces of the last matched scan in base_link at stamp_s.
  std::vector<LineObservation> WallObservations(double stamp_s) const;
  // T_odom_base at stamp_s, interpolated in the history (clamped).
  core::SE2 OdometryAt(double stamp_s) const;
  // Stamp of the newest scan received (-inf before any).
  double last_scan_received_s() const { return last_received_s_; }

 private:
  void MatchCovered(double up_to_s, LocalizerCounters* counters);
  // A sweep's ray times: ray i at first_ray_s + i * time_increment_s.
  struct SweepTiming {
    double first_ray_s = 0.0;
    double time_increment_s = 0.0;
  };
  SweepTiming Sweep(const core::LaserScan& scan) const;
  // The vehicle's motion over a sweep that describes describes_s, where the
  // odometry is T_odom_base: one constant twist (zero without deskewing).
  core::Vector3 SweepTwist(double describes_s, const core::SE2& T_odom_base) const;
  // T_odom_base at time t of the last matched scan's sweep, by that twist.
  core::SE2 LastSweepPose(double t) const;

  LidarSetup setup_;
  lidar::ScanPointsOptions points_options_;
  bool deskew_ = true;
  double deskew_window_s_ = 0.1;
  std::vector<core::SE2> beam_poses_;  // per ray, reused from scan to scan
  lidar::WallLineOptions wall_options_;
  double history_s_;
  lidar::ScanOdometryOptions scan_odometry_options_;
  double max_scan_gap_s_;
  int local_map_scans_;
  int scans_in_local_map_ = 0;
  // Left factor on the wheel odometry given to the scan odometry: a renewed
  // one continues from the previous one's estimate, or from a
  // re-initialization's pose (T_fix * odometry).
  core::SE2 T_fix_;
  std::unique_ptr<lidar::ScanOdometry> scan_odometry_;
  double last_matched_s_;
  core::Trajectory odometry_;  // T_odom_base at the wheel readings, recent history
  double start_s_ = 0.0;
  bool started_ = false;
  // Queued scans and the instant each describes (mid-sweep), in time order.
  std::deque<std::pair<double, core::LaserScan>> queue_;
  std::optional<core::LaserScan> last_;               // the last scan matched
  double last_describes_s_ = 0.0;                     // the instant last_ describes
  core::SE2 last_T_odom_base_;                        // the odometry at that instant
  core::Vector3 last_twist_ = core::Vector3::Zero();  // its sweep's twist
  double last_received_s_;
  ScanSink sink_;
};

}  // namespace groundline::localization::internal

#endif  // GROUNDLINE_LOCALIZATION_SRC_LOCALIZER_LIDAR_H_
