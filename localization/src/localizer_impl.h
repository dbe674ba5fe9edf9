// The state of a Localizer (localizer.h). Private to the localization library.
#ifndef GROUNDLINE_LOCALIZATION_SRC_LOCALIZER_IMPL_H_
#define GROUNDLINE_LOCALIZATION_SRC_LOCALIZER_IMPL_H_

#include <deque>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "groundline/localization/floor_flow_tracker.h"
#include "groundline/localization/localizer.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/perception/line_extractor.h"
#include "groundline/localization/atlas_mapper.h"
#include "localizer_lidar.h"

namespace groundline::localization::internal {

// Stamps within this of each other are the same instant (text round trips).
inline constexpr double kSameInstantS = 1e-9;

class LocalizerImpl {
 public:
  static core::Result<std::unique_ptr<LocalizerImpl>> Create(const LocalizerOptions& options,
                                                             LocalizerSetup setup);

  core::Status SetInitialPose(double stamp_s, const core::SE2& T_map_base,
                              const core::Matrix3& covariance);
  core::Status RequestRelocalization();
  // The reading in source time; its output in the localizer's time.
  std::optional<KeyframeOutput> AddWheelReading(const core::WheelEncoderReading& reading);
  // Moves an output's stamps from the localizer's time to the source's.
  void ToSourceTime(KeyframeOutput& k) const;
  void AddFrame(double stamp_s, Localizer::FrameLoader load,
                std::optional<ConvertedObservations> observations);
  void AddScan(core::LaserScan scan);
  std::optional<PoseEstimate> PoseAt(double stamp_s) const;
  SensorState Sensors() const;

  struct PendingFrame {
    double stamp_s = 0.0;
    Localizer::FrameLoader load;
    std::optional<ConvertedObservations> observations;
  };

  LocalizerOptions options;
  LocalizerSetup setup;
  LocalizerCounters counters;
  std::unique_ptr<SlidingWindowSmoother> smoother;  // kLines, kMapping
  std::unique_ptr<LidarStage> lidar;
  std::unique_ptr<AtlasMapper> mapper;  // kMapping with the LiDAR
  Atlas walls;  // the atlas' face lines (wall counts)
  std::unique_ptr<Relocalizer> relocalizer;
  std::optional<OdometryIntegrator> relocalizer_odometry;
  std::optional<PoseEstimate> relocalized;

  bool started = false;
  core::SE2 T_map_start;
  // Left factor on the dead reckoning T_map_start * T_odom_base (kOdometry's
  // estimate, kLidar's prediction): a re-initialization moves it to the
  // given pose; the LiDAR stage is given the odometry without it, continuous.
  core::SE2 T_reinit;
  std::optional<OdometryIntegrator> odometry;
  KeyframeSelector selector{KeyframeSelector::Options()};
  PoseEstimate keyframe;  // kOdometry / kLidar: the last keyframe's estimate
  core::SE2 T_odom_keyframe;
  PoseEstimate current;
  std::deque<PoseEstimate> history;  // odometry-rate poses, newest last
  // The wheel odometry at history's stamps: T_odom_base, its covariance.
  std::deque<PoseEstimate> odometry_history;
  // A re-initialization stamped after the newest reading (SetInitialPose),
  // in localizer time: applied when the odometry reaches its stamp.
  std::optional<PoseEstimate> pending_pose;
  std::optional<PendingFrame> pending;
  // The camera front end's frame-sized buffers, reused from frame to frame.
  cv::Mat bev;
  std::optional<FloorFlowTracker> flow_tracker;  // options.track_floor_texture
  perception::ExtractionScratch extraction_scratch;
  std::optional<double> last_reading_s;
  double last_frame_s = -std::numeric_limits<double>::infinity();
  double last_frame_used_s = -std::numeric_limits<double>::infinity();
  double last_scan_match_s = -std::numeric_limits<double>::infinity();
  double path_length_m = 0.0;
  double last_speed_mps = 0.0;  // of the last accepted reading
  bool odometry_frozen = false;
  // The newest reading's time when one was not finite or frozen.
  double last_odometry_fault_s = -std::numeric_limits<double>::infinity();
  bool odometry_fault_pending = false;
  // Coasting (Coast): since when, and the wheel speeds of the last good reading.
  bool coasting = false;
  double coast_since_s = 0.0;
  double last_left_radps = 0.0, last_right_radps = 0.0;
  bool wheel_speeds_known = false;  // last_*_radps come from a taken reading
  long keyframe_index = 0;
  bool relocalizer_done_ = false;  // committed: the relocalizer is kept for its status

  // Time (LocalizerOptions::clock_jump_readings): the localizer's time is
  // the source's plus clock_offset_s, which grows by each backward jump, so
  // that every stamp inside stays increasing. Stamps below are the localizer's.
  double clock_offset_s = 0.0;
  std::deque<double> recent_stamps;  // of the readings taken, reorder_tolerance_s back
  double late_left_rad = 0.0, late_right_rad = 0.0;  // late increments for the next reading
  // Out-of-order readings in order among themselves: a jump, once long enough.
  std::vector<core::WheelEncoderReading> jump_run;

 private:
  void Start(double stamp_s, const core::SE2& T_map_base, const core::Matrix3& covariance);
  // SetInitialPose after the start: the time rules, then Reinitialize now
  // or later (pending_pose).
  core::Status Restart(const PoseEstimate& given);
  // The estimate restarts at the newest reading from `given` (stamped
  // within odometry_history), carried there by the wheel odometry
  // (localizer_reinit.cc).
  void Reinitialize(const PoseEstimate& given);
  std::optional<KeyframeOutput> Relocalize(const core::WheelEncoderReading& reading);
  // A reading at or before the newest one: a duplicate, late (merged), out
  // of order, or part of a backward clock jump.
  std::optional<KeyframeOutput> BehindReading(const core::WheelEncoderReading& reading);
  // A reading after the newest one (localizer time).
  std::optional<KeyframeOutput> TakeReading(core::WheelEncoderReading reading);
  // A reading whose increments are not finite or frozen: the estimate
  // coasts on the last wheel speeds with a growing covariance
  // (LocalizerOptions::max_coast_s), so that the outputs, the LiDAR and the
  // lines go on.
  std::optional<KeyframeOutput> Coast(double stamp_s);
  // The difference of the wheels' speeds over the reading differs from the
  // last taken reading's by more than slip_speed_difference_change_mps.
  bool IsWheelSlip(const core::WheelEncoderReading& r, double gap_s) const;
  // Adds the covariance of unknown motion to the odometry: speed and yaw-rate
  // errors of odometry_gap_speed_mps / _yaw_rate_radps over seconds2 [s^2]
  // (a gap of T: T^2; a coast from T0 to T1: T1^2 - T0^2).
  void WidenByUnknownMotion(double seconds2);
  // Integrates a reading taken (or coasted), the keyframe decision, the outputs.
  std::optional<KeyframeOutput> Advance(const core::WheelEncoderReading& reading,
                                        std::optional<double> previous_s);
  // Integrates `fraction` of the reading's increments, up to stamp_s.
  void Integrate(const core::WheelEncoderReading& reading, double fraction, double stamp_s);
  // The keyframe decision at stamp_s, with the frame whose turn it is.
  std::optional<KeyframeOutput> Step(double stamp_s, std::optional<PendingFrame> frame);
  std::optional<KeyframeOutput> FloorKeyframe(double stamp_s, std::optional<PendingFrame> frame);
  // The frame's observations stamped stamp_s; nullopt when unreadable.
  std::optional<ConvertedObservations> Observe(PendingFrame& frame, double stamp_s);
  void UpdateCurrent(double stamp_s);
  core::SE2 DeadReckoning() const { return T_reinit * T_map_start * odometry->T_odom_base(); }
  void CountLidar(const lidar::ScanOdometryKeyframe& k);
};

}  // namespace groundline::localization::internal

#endif  // GROUNDLINE_LOCALIZATION_SRC_LOCALIZER_IMPL_H_
