// The configuration of `groundline serve` (docs/service.md lists every key
// with its default). Read from YAML at the edge; every error names the file,
// the line and the key, and what was expected.
#ifndef GROUNDLINE_SERVICE_SERVICE_CONFIG_H_
#define GROUNDLINE_SERVICE_SERVICE_CONFIG_H_

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::perception {
struct BevExtent;
}  // namespace groundline::perception

namespace groundline::service {

// A sensor fault injected into the replay (tests and the fault table; a
// vehicle's config has none): over [from_s, to_s) of data time after the
// replay's first event.
struct InjectedFault {
  enum class Sensor { kCamera, kLidar, kOdometry, kClock } sensor = Sensor::kCamera;
  // camera: silent (unplugged: no frames), blackout (black frames), corrupt
  // (undecodable frames); lidar: silent; odometry: nan (non-finite
  // increments), frozen (zero increments while the vehicle moves), reorder
  // (every other pair of readings swapped in transport), duplicate (every
  // reading delivered twice); clock: jump (every stamp of every sensor from
  // from_s on moves by by_s; to_s is not used).
  std::string kind;
  double from_s = 0.0;
  double to_s = 0.0;
  double by_s = 0.0;  // clock jump [s] (< 0: back)
};

// inputs.dds: the sensor streams from ROS 2 topics over DDS (docs/dds.md)
// instead of the replay's logs. The domain id is ROS_DOMAIN_ID's; the network
// CYCLONEDDS_URI's (unset: loopback only).
struct DdsInputConfig {
  bool enabled = false;              // the key inputs.dds is present
  std::string odometry = "odom";     // odom (nav_msgs/Odometry) | joint_states
  bool scan = true;                  // rt/scan
  bool image = false;                // rt/camera/image_raw (mono8)
  bool initial_pose = true;          // rt/initialpose
  std::string ros_namespace;         // "agv7": rt/agv7/odom, ...
  std::string stamp_check = "wall";  // wall | newest | none (io::StampReference)
  std::string qos = "sensor_data";   // sensor_data (best effort, depth 5) | lossless
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::string lidar_frame = "laser";
  std::string camera_frame;  // empty: any
  std::string left_wheel_joint = "left_wheel_joint";
  std::string right_wheel_joint = "right_wheel_joint";
};

// output.dds: the pose, the map -> odom transform and the health on ROS 2 topics.
struct DdsOutputConfig {
  bool enabled = false;
  bool pose = true;         // rt/groundline/pose at every keyframe
  bool tf = true;           // rt/tf map -> odom at every wheel reading
  bool diagnostics = true;  // rt/diagnostics every diagnostics_period_s
  std::string ros_namespace;
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  // map -> odom is stamped this far after the reading it was computed at, as
  // nav2 AMCL's transform_tolerance (a transform valid a little ahead) [s].
  double transform_tolerance_s = 0.1;
  double diagnostics_period_s = 1.0;
};

struct ServiceConfig {
  // inputs.replay: a dataset replayed with its timestamps honoured. With
  // inputs.dds it only sets the localizer up (calibration, wheel and LiDAR
  // geometry, floor map, start pose): its logs are not replayed.
  std::string replay_dataset;  // required
  double replay_speed = 1.0;   // 1: real time; N: N times faster; 0: as fast as possible
  // Replays the dataset this many times, each pass shifted in time to follow
  // the previous one (a closed-loop drive as a long shift).
  int replay_loops = 1;
  std::vector<InjectedFault> faults;  // inputs.replay.faults
  // inputs.camera.uri: the frames from a camera (io/frame_source.h: v4l2:,
  // libcamera:, folder:) instead of the replay's own; a folder is paced to
  // the replay's clock by its index stamps. Empty: the replay's frames.
  std::string camera_uri;
  DdsInputConfig dds_inputs;
  // localizer
  std::string preset = "fusion";  // fusion | lines | odometry | lidar
  std::string atlas;              // empty: the dataset's floor map
  // localizer.odometry_calibration: the vehicle's odometry calibration file
  // (`groundline localize --odometry-out`); empty: the manifest's nominal
  // wheel geometry and the preset's noise.
  std::string odometry_calibration;
  // localizer.self_calibration: estimate the camera mount from the floor
  // lines while driving (docs/self_calibration.md); health.jsonl gets the
  // selfcal_* fields. Needs a preset that reads the camera (fusion, lines).
  bool self_calibration = false;
  // localizer.keep_atlas_current: keep the atlas current while localizing
  // (markings born, vanished ones retired: docs/atlas.md) and write it to
  // output.dir/atlas.json at the stop. Needs the fusion or lines preset.
  bool keep_atlas_current = false;
  // localizer.bev: the camera's bird's-eye view (perception::BevExtent): x_m
  // [near, far] ahead and y_m [right, left] in base_link, metres, each by
  // default the camera's floor footprint; cell_m, the cell side.
  std::optional<std::array<double, 2>> bev_x_m;
  std::optional<std::array<double, 2>> bev_y_m;
  double bev_cell_m = 0.01;
  // The localizer.bev keys as the perception module takes them.
  perception::BevExtent Bev() const;
  // localizer.mount_estimate: where the self-calibration keeps its estimate
  // across restarts (written after every update, read at the start);
  // empty: output.dir/mount_estimate.json.
  std::string mount_estimate;
  // start: initial_pose [x_m, y_m, yaw_deg], else relocalize, else the
  // dataset's start pose (or the saved state when resume is on).
  std::optional<std::array<double, 3>> initial_pose;
  bool relocalize = false;
  bool resume = true;  // start from output.dir/state.json when it exists
  // Start from the first accepted rt/initialpose (inputs.dds.initial_pose)
  // instead of the dataset's start pose.
  bool wait_for_initial_pose = false;
  // output
  std::string output_dir;  // required
  DdsOutputConfig dds_outputs;
  // http: the status page and health endpoint
  bool http_enabled = true;
  std::string http_address = "127.0.0.1";
  int http_port = 8088;  // 0: any free port (reported at start)
  // queues (per stage, bounded; a full camera queue drops the oldest frame)
  int camera_queue_depth = 2;
  // The estimator holds a wheel reading at most this long for a frame of its
  // time still in the camera stage [s].
  double max_frame_wait_s = 0.05;

  core::Status Validate() const;
};

// Reads and validates a config file. Unknown keys are errors (a typo must
// not silently fall back to a default).
core::Result<ServiceConfig> ReadServiceConfig(const std::filesystem::path& path);

}  // namespace groundline::service

#endif  // GROUNDLINE_SERVICE_SERVICE_CONFIG_H_
