// The state and stages of a Service (service.h). Private to the service library.
#ifndef GROUNDLINE_SERVICE_SRC_SERVICE_IMPL_H_
#define GROUNDLINE_SERVICE_SRC_SERVICE_IMPL_H_

#include "groundline/service/service.h"

#include <unistd.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <deque>
#include <fstream>
#include <limits>
#include <mutex>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <thread>

#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/dataset_streams.h"
#include "groundline/core/run_timing.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/io/dds_inputs.h"
#include "groundline/io/dds_outputs.h"
#include "groundline/io/frame_source.h"
#include "groundline/localization/keyframe_mount_calibration.h"
#include "groundline/localization/localizer_json.h"
#include "groundline/localization/odometry_integrator.h"
#include "groundline/service/dataset_localizer.h"
#include "groundline/service/replay.h"
#include "service_queues.h"
#include "status_page.h"

// Last: <resolv.h>, which it includes, defines the macro _res that Eigen uses as a name.
#include <httplib.h>

namespace groundline::service {

// Names shared by service.cc and service_stages.cc.

namespace fs = std::filesystem;
namespace loc = localization;
using core::Percentile;
using core::ThreadCpuSeconds;
using localization::KeyframeSelector;
using Clock = std::chrono::steady_clock;
using internal::BoundedQueue;

struct FrameJob {
  double stamp_s = 0.0;
  fs::path path;
  cv::Mat grey;  // a camera's decoded frame (else decoded from path)
  Clock::time_point arrived;
  // Injected faults (InjectedFault): a black frame, or one that does not decode.
  bool black = false;
  bool corrupt = false;
  std::uint64_t seq = 0;  // arrival order among all inputs (Service::Impl::input_seq)
};

// Resident set size [MB] (/proc/self/statm).
inline double ResidentMb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1048576.0;
}
struct Observed {
  loc::ConvertedObservations observations;
  Clock::time_point arrived;
  std::uint64_t seq = 0;  // its frame's arrival order
};
struct EstimatorEvent {
  enum class Kind { kWheel, kScan, kInitialPose } kind = Kind::kWheel;
  core::WheelEncoderReading wheel;
  // kWheel from nav_msgs/Odometry: the robot's own odom pose at the reading
  // (map -> odom is computed against it); else the service integrates one.
  std::optional<core::SE2> T_odom_base;
  core::LaserScan scan;
  io::PlanarPoseStamped initial_pose;  // kInitialPose (rt/initialpose)
  std::uint64_t seq = 0;               // arrival order among all inputs (PushEvent)
};
// A wheel reading waiting in the estimator for the frame of its time.
// A wheel reading waiting for the frames of its time, or a scan that came
// after it (scans keep their place in the arrival order, so that a clock step
// the readings reveal comes before the scans on the new clock).
struct HeldReading {
  core::WheelEncoderReading reading;
  std::optional<core::SE2> T_odom_base;
  std::chrono::steady_clock::time_point since;
  std::optional<core::LaserScan> scan;  // set: a scan, not a reading
  std::uint64_t seq = 0;
};

inline loc::LocalizerOptions PresetOptions(const std::string& preset) {
  if (preset == "fusion") return loc::LocalizerOptions::ForFusion();
  if (preset == "lines") {
    loc::LocalizerOptions o = loc::LocalizerOptions::ForFusion();
    o.use_lidar = false;
    return o;
  }
  loc::LocalizerOptions o;
  o.mode = preset == "lidar" ? loc::LocalizerMode::kLidar : loc::LocalizerMode::kOdometry;
  return o;
}

struct Service::Impl {
  ServiceConfig config;
  core::Dataset dataset;
  std::unique_ptr<loc::Localizer> localizer;
  // localizer.self_calibration: fed by the estimator thread's keyframes.
  std::optional<loc::KeyframeMountCalibration> self_calibration;
  // Where the estimate is kept across restarts (written after every window
  // it fuses), and what the start did with a saved one.
  std::filesystem::path mount_estimate_path;
  std::string mount_estimate_restored;
  std::atomic<long> mount_estimate_write_failures{0};
  // The mount the camera stage rebuilds its front end with next (set by the
  // estimator thread, taken by the camera thread).
  std::mutex mount_mutex;
  std::optional<loc::KeyframeMountCalibration::MountUpdate> pending_mount;
  std::atomic<long> mount_rebuilds{0}, mount_rebuild_failures{0};
  // The camera thread's own after the start (rebuilt there for a new mount).
  std::shared_ptr<const loc::FloorFrontEnd> camera;
  loc::Atlas atlas;
  std::optional<loc::PoseEstimate> start;
  double resume_after_s = -std::numeric_limits<double>::infinity();
  bool relocalize = false;

  std::unique_ptr<BoundedQueue<FrameJob>> frames;
  BoundedQueue<EstimatorEvent> events{4096};
  BoundedQueue<Observed> observed{64};
  // Stamps of the frames in the camera stage (queued or being processed).
  std::mutex pending_mutex;
  std::multiset<double> pending_frames;
  std::atomic<long> camera_dropped{0}, camera_unreadable{0}, camera_processed{0};
  std::atomic<long> camera_not_due{0};
  // Observations that never met a wheel reading of their time: the oldest
  // beyond kMaxObservationsWaiting while the wheel readings are silent, and
  // those still waiting when the inputs end.
  std::atomic<long> observations_without_odometry{0};
  // About the span of the 4096-event input queue with a 30 fps camera: a
  // replay as fast as possible never has more waiting.
  static constexpr std::size_t kMaxObservationsWaiting = 1024;
  // The estimator's odometry since its last keyframe, for the camera stage:
  // a frame taken while the vehicle is far from the next keyframe is not
  // extracted (it would be skipped), which keeps a 30 fps camera cheap.
  std::atomic<double> since_keyframe_m{1e9}, since_keyframe_rad{1e9};
  std::atomic<double> since_stamp_s{0.0}, speed_mps{0.0}, yaw_rate_radps{0.0};
  double not_due_fraction = 0.8;

  // Shared with the HTTP thread.
  mutable std::mutex status_mutex;
  nlohmann::ordered_json last_keyframe;
  loc::PoseEstimate pose;
  loc::LocalizerCounters counters;
  // The input counters over the last kRateWindowS of data (a sample every
  // 0.1 s of data), from which /health.json gives rates per second of data.
  struct RateSample {
    double stamp_s;
    long wheel_readings, frames, scans;
  };
  static constexpr double kRateWindowS = 2.0;
  std::deque<RateSample> rate_samples;
  std::vector<std::uint8_t> bev_png;
  std::string atlas_json;
  std::vector<double> latency_ms;
  // (data time since the first reading [s], RSS [MB]) every 600 s of data.
  std::vector<std::pair<double, double>> rss_samples;
  std::optional<double> first_reading_s;
  // The newest wheel reading's stamp (data time; NaN before the first): the
  // memory thread trims the heap by it.
  std::atomic<double> newest_reading_s{std::numeric_limits<double>::quiet_NaN()};
  // The heap trims, under status_mutex.
  long memory_trims = 0;
  double trim_ms_total = 0.0, trim_ms_max = 0.0;
  // Data time of the replay's first event, and per injected fault: whether a
  // keyframe reported the degradation, and when the mode was "full" again.
  double replay_first_s = 0.0;
  struct FaultTrack {
    bool degraded_seen = false;
    std::optional<double> recovered_at_s;
  };
  std::vector<FaultTrack> fault_tracks;
  double cpu_replay_s = 0.0, cpu_camera_s = 0.0, cpu_estimator_s = 0.0;
  long odometry_out = 0;

  // inputs.camera: frames from a FrameSource on their own thread.
  std::atomic<double> replay_now_s{-1e300};
  // The newest frame handed to the camera stage (stamp, wall time) and the
  // frame period seen: a reading at or past the next frame's expected time
  // waits (max_frame_wait_s) for it, unless the camera has stalled.
  std::atomic<double> frame_watermark_s{-1e300}, frame_period_s{0.0};
  std::atomic<Clock::rep> frame_wall_ticks{0};
  std::atomic<long> camera_source_errors{0}, camera_reopens{0};
  void CameraInput(const std::atomic<bool>& done);
  void PushFrame(FrameJob job);
  // Every input in arrival order: frames (PushFrame) and events (PushEvent)
  // share one sequence, which tells the estimator what came after what when
  // the stamps cannot (a clock that stepped back).
  std::atomic<std::uint64_t> input_seq{0};
  void PushEvent(EstimatorEvent event) {
    event.seq = input_seq++;
    events.PushWait(std::move(event));
  }

  // inputs.dds / output.dds (service_dds.cc). The inputs are polled by the
  // input loop (Run's thread); the outputs are written by the estimator.
  std::optional<io::DdsParticipant> dds;
  std::optional<io::DdsInputs> dds_inputs;
  std::optional<io::DdsOutputs> dds_outputs;
  // The input loop's conversion of nav_msgs/Odometry to wheel readings.
  std::optional<core::SE2> dds_last_T_odom_base;
  localization::DiffDriveParams drive;
  // The odom frame of readings without one of their own (the replay, joint
  // states): the service's own integration of the wheel readings.
  std::optional<loc::OdometryIntegrator> own_odom;
  // Snapshots and counts for the health (under status_mutex).
  std::array<io::DdsInputCounters, io::kNumDdsInputs> dds_counters;
  std::array<std::uint32_t, io::kNumDdsInputs> dds_matched{};
  long dds_poll_errors = 0, initial_poses_applied = 0, initial_poses_refused = 0;
  std::string dds_last_error, initial_pose_last_error;
  long dds_poses_out = 0, dds_tf_out = 0, dds_diagnostics_out = 0, dds_write_errors = 0;
  Clock::time_point dds_last_diagnostics{};
  loc::LocalizerCounters dds_diag_counters;  // counters at the last diagnostics, for rates
  core::Status CreateDds();
  void DdsInputLoop(const std::atomic<bool>& stop);
  // After an accepted reading (status_mutex held): map -> odom, and at
  // keyframes the pose; diagnostics every diagnostics_period_s.
  void PublishDds(const core::SE2* T_odom_base, const std::optional<loc::KeyframeOutput>& keyframe);
  void PublishDiagnostics();
  nlohmann::ordered_json DdsJson() const;

  httplib::Server http;
  int port = 0;
  std::thread http_thread;

  void CameraStage();
  void EstimatorStage(std::ofstream& keyframes, std::ofstream& odometry, std::ofstream& health);
  void ReleasePending(double stamp_s) {
    std::lock_guard<std::mutex> lock(pending_mutex);
    if (auto it = pending_frames.find(stamp_s); it != pending_frames.end())
      pending_frames.erase(it);
  }
  // A frame in the camera stage stamped in [stamp_s - lag_s, stamp_s]: one
  // further behind would be too late for the localizer anyway (its
  // max_frame_lag_s), e.g. a frame on a clock that has stepped back.
  bool FramePendingAtOrBefore(double stamp_s, double lag_s) {
    std::lock_guard<std::mutex> lock(pending_mutex);
    const auto it = pending_frames.lower_bound(stamp_s - lag_s - 1e-9);
    return it != pending_frames.end() && *it <= stamp_s + 1e-9;
  }
};

}  // namespace groundline::service

#endif  // GROUNDLINE_SERVICE_SRC_SERVICE_IMPL_H_
