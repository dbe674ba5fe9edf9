#include "localizer_lidar.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "groundline/core/trajectory_association.h"

namespace groundline::localization::internal {

LidarStage::LidarStage(const LidarSetup& setup, const LocalizerOptions& options)
    : setup_(setup),
      points_options_(options.scan_points),
      deskew_(options.deskew_scans),
      deskew_window_s_(options.deskew_motion_window_s),
      wall_options_(options.walls),
      history_s_(options.odometry_history_s),
      scan_odometry_options_(options.scan_odometry),
      max_scan_gap_s_(options.max_scan_gap_s),
      local_map_scans_(options.lidar_local_map_scans),
      scan_odometry_(std::make_unique<lidar::ScanOdometry>(options.scan_odometry)),
      last_matched_s_(-std::numeric_limits<double>::infinity()),
      last_received_s_(-std::numeric_limits<double>::infinity()) {}

void LidarStage::Start(double stamp_s, const core::SE2& T_odom_base) {
  start_s_ = stamp_s;
  started_ = true;
  odometry_.clear();
  odometry_.push_back({stamp_s, T_odom_base, std::nullopt});
  while (!queue_.empty() && queue_.front().first <= stamp_s) queue_.pop_front();
}

bool LidarStage::AddScan(core::LaserScan scan, LocalizerCounters* counters) {
  ++counters->scans;
  bool finite = std::isfinite(scan.stamp_s) && std::isfinite(scan.angle_min_rad) &&
                std::isfinite(scan.angle_increment_rad) && scan.angle_increment_rad != 0.0 &&
                std::isfinite(scan.range_max_m) && !scan.ranges_m.empty();
  for (double r : scan.ranges_m) finite = finite && !std::isnan(r);
  if (!finite) {
    ++counters->scans_dropped_bad;
    return false;
  }
  // The instant the scan describes: the middle of its sweep (scan_odometry.h).
  double describes_s = scan.stamp_s;
  if (setup_.stamp == core::LidarStamp::kFirstRay) {
    describes_s +=
        lidar::MidSweepOffsetS(scan.ranges_m.size(), scan.angle_increment_rad, setup_.rate_hz);
  }
  if (describes_s <= last_received_s_) {
    ++counters->scans_dropped_out_of_order;
    return false;
  }
  if (started_ && describes_s <= start_s_) {
    ++counters->scans_before_start;
    last_received_s_ = describes_s;
    return false;
  }
  last_received_s_ = describes_s;
  queue_.emplace_back(describes_s, std::move(scan));
  // Before the start nothing is matched: keep only the recent scans.
  while (!started_ && queue_.front().first < describes_s - history_s_) queue_.pop_front();
  return true;
}

void LidarStage::AddOdometry(double stamp_s, const core::SE2& T_odom_base,
                             LocalizerCounters* counters) {
  odometry_.push_back({stamp_s, T_odom_base, std::nullopt});
  // Keep history_s_ of odometry (and at least two readings) for interpolation.
  std::size_t drop = 0;
  while (drop + 2 < odometry_.size() && odometry_[drop + 1].stamp_s < stamp_s - history_s_) ++drop;
  if (drop > 64) odometry_.erase(odometry_.begin(), odometry_.begin() + static_cast<long>(drop));
  MatchCovered(stamp_s, counters);
}

void LidarStage::MatchCovered(double up_to_s, LocalizerCounters* counters) {
  while (!queue_.empty() && queue_.front().first <= up_to_s) {
    auto [describes_s, scan] = std::move(queue_.front());
    queue_.pop_front();
    // After a silent LiDAR the local map and the last match are stale: a
    // match across the gap would be a guess, so the scan odometry restarts.
    if (std::isfinite(last_matched_s_) && describes_s - last_matched_s_ > max_scan_gap_s_) {
      scan_odometry_ = std::make_unique<lidar::ScanOdometry>(scan_odometry_options_);
      scans_in_local_map_ = 0;
      last_.reset();
      ++counters->lidar_restarts;
    }
    last_matched_s_ = describes_s;
    beam_poses_.clear();
    const core::SE2 T_odom_base = OdometryAt(describes_s);
    const core::Vector3 twist = SweepTwist(describes_s, T_odom_base);
    if (deskew_) {
      const SweepTiming sweep = Sweep(scan);
      for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
        const double dt_s =
            sweep.first_ray_s + static_cast<double>(i) * sweep.time_increment_s - describes_s;
        beam_poses_.push_back(core::SE2::Exp(dt_s * twist) * setup_.T_base_lidar);
      }
    }
    const lidar::ScanPoints points = lidar::ScanPointsFromRanges(
        scan.ranges_m, scan.angle_min_rad, scan.angle_increment_rad, scan.range_max_m,
        setup_.T_base_lidar, beam_poses_, points_options_);
    ++scans_in_local_map_;
    if (sink_) sink_(describes_s, T_odom_base, points);
    core::Result<lidar::ScanReport> report =
        scan_odometry_->AddScan(describes_s, T_fix_ * T_odom_base, points);
    if (!report.ok()) {
      ++counters->lidar_failures;
      continue;
    }
    counters->scans_matched += report->matched;
    last_ = std::move(scan);
    last_describes_s_ = describes_s;
    last_T_odom_base_ = T_odom_base;
    last_twist_ = twist;
  }
}

lidar::ScanOdometryKeyframe LidarStage::Keyframe(double stamp_s, LocalizerCounters* counters) {
  const core::SE2 T_odom_base = OdometryAt(stamp_s);
  lidar::ScanOdometryKeyframe k = scan_odometry_->Keyframe(stamp_s, T_fix_ * T_odom_base);
  if (local_map_scans_ > 0 && scans_in_local_map_ >= local_map_scans_) {
    // The fresh scan odometry starts where this one's estimate is now.
    Renew(stamp_s, k.T_odom_base);
    ++counters->lidar_local_map_renewals;
  }
  return k;
}

void LidarStage::Renew(double stamp_s, const core::SE2& T_map_base) {
  T_fix_ = T_map_base * OdometryAt(stamp_s).Inverse();
  scan_odometry_ = std::make_unique<lidar::ScanOdometry>(scan_odometry_options_);
  scans_in_local_map_ = 0;
}

core::SE2 LidarStage::OdometryAt(double stamp_s) const {
  return core::InterpolatePose(odometry_, stamp_s);
}

std::vector<LineObservation> LidarStage::WallObservations(double stamp_s) const {
  if (!last_) return {};
  const core::LaserScan& scan = *last_;
  // Each ray is moved from its own time by the sweep's motion the matcher
  // used (one model of the sweep for both).
  const SweepTiming sweep = Sweep(scan);
  const std::vector<lidar::RangePoint> points = lidar::RangePointsAt(
      scan.ranges_m, scan.angle_min_rad, scan.angle_increment_rad, sweep.first_ray_s,
      sweep.time_increment_s, setup_.T_base_lidar, OdometryAt(stamp_s),
      [this](double t) { return LastSweepPose(t); },
      std::max(wall_options_.min_range_m, scan.range_min_m),
      std::min(wall_options_.max_range_m, scan.range_max_m));
  return lidar::WallLineObservations(lidar::ExtractWallLines(points, wall_options_));
}

core::Vector3 LidarStage::SweepTwist(double describes_s, const core::SE2& T_odom_base) const {
  if (!deskew_) return core::Vector3::Zero();
  // The odometry's mean twist over the window that ends at the scan's
  // instant, continued over the sweep (so that the scan is matched as soon
  // as the odometry reaches that instant).
  return OdometryAt(describes_s - deskew_window_s_).Between(T_odom_base).Log() / deskew_window_s_;
}

core::SE2 LidarStage::LastSweepPose(double t) const {
  return last_T_odom_base_ * core::SE2::Exp((t - last_describes_s_) * last_twist_);
}

LidarStage::SweepTiming LidarStage::Sweep(const core::LaserScan& scan) const {
  SweepTiming t;
  // A rotating mirror: one revolution per scan period, rays in angle order.
  t.time_increment_s =
      std::abs(scan.angle_increment_rad) / (setup_.rate_hz * 2.0 * std::numbers::pi);
  t.first_ray_s =
      setup_.stamp == core::LidarStamp::kFirstRay
          ? scan.stamp_s
          : scan.stamp_s - lidar::MidSweepOffsetS(scan.ranges_m.size(), scan.angle_increment_rad,
                                                  setup_.rate_hz);
  return t;
}

}  // namespace groundline::localization::internal
