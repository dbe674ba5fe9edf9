// The sensor inputs of the localization service over ROS 2 topics: takes
// odometry, wheel joint states, scans, images and initial poses, validates
// them (dds_validate.h), converts them to groundline types and hands them to
// one callback per message type. Invalid messages are dropped and counted,
// never passed on.
//
// Order: each Poll takes everything that arrived on every topic and delivers
// the sensor messages merged by stamp (initial poses first). Across Polls the
// order is that of arrival, so a message that arrives late on one topic can
// follow a later-stamped one of another topic; each sensor topic on its own
// is strictly increasing in stamp (anything else is dropped). Initial poses
// are commands: each is taken on its own, whatever its stamp (the
// localizer's time rules judge it), and none moves the sensors' stamp
// reference (StampReference::kNewest).
//
// Driving it: call Poll() from the service's input loop (or a thread of its
// own); callbacks run inside Poll, on the calling thread. Not thread-safe.
// The participant must outlive the object.
#ifndef GROUNDLINE_IO_DDS_INPUTS_H_
#define GROUNDLINE_IO_DDS_INPUTS_H_

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <opencv2/core/mat.hpp>

#include "groundline/core/dataset_records.h"
#include "groundline/core/status.h"
#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_entities.h"
#include "groundline/io/dds_validate.h"

namespace groundline::io {

enum class DdsInput { kOdometry = 0, kJointState, kScan, kImage, kInitialPose };
inline constexpr int kNumDdsInputs = 5;
const char* DdsInputName(DdsInput input);

// Which stamp incoming stamps are checked against.
enum class StampReference {
  kNone,       // no stamp check
  kWallClock,  // the system clock (live robots; ROS stamps are wall time)
  kNewest,     // the newest stamp accepted on any input (replays with their own clock)
};

struct DdsInputsOptions {
  // An empty topic name is not subscribed (nor is a topic without a callback).
  std::string odometry_topic = "rt/odom";
  std::string joint_state_topic = "rt/joint_states";
  std::string scan_topic = "rt/scan";
  std::string image_topic = "rt/camera/image_raw";
  std::string initial_pose_topic = "rt/initialpose";
  // Expected frame ids; an empty one accepts any.
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::string lidar_frame = "laser";
  std::string camera_frame;
  // Joint names of the drive wheels in sensor_msgs/JointState.
  std::string left_wheel_joint = "left_wheel_joint";
  std::string right_wheel_joint = "right_wheel_joint";
  StampReference stamp_reference = StampReference::kWallClock;
  // QoS of the sensor readers (odometry, joint states, scans, images). The
  // best-effort default matches every ROS 2 sensor writer; kLossless is for
  // tests against a kLossless writer.
  QosPreset sensor_qos = QosPreset::kSensorData;
  DdsStampWindow stamp_window;
  // A message whose stamp is not after the previous one of its topic is
  // dropped (counted): odometry and joint states are absolute, so an older
  // one carries no motion the newer did not. But this many consecutive
  // older messages, each after the one before, are the sender's clock
  // stepping back: from the last of them on, the topic's order restarts
  // (counted in clock_steps), and the consumer sees the step (the localizer
  // absorbs it: docs/localization.md, "Time").
  int clock_step_messages = 10;

  // Ok if the window is valid, at least one topic is set, topic names start
  // with "rt/" and the wheel joint names are distinct and non-empty.
  core::Status Validate() const;
};

struct DdsInputCallbacks {
  // Wheel increments from joint states: the first message gives zero deltas
  // (the dataset convention), each later one the change of the joint angles
  // (absolute angles, not wrapped, as ros2_control's joint_state_broadcaster
  // publishes them).
  std::function<void(const core::WheelEncoderReading&)> on_wheels;
  std::function<void(const PlanarOdometry&)> on_odometry;
  std::function<void(const core::LaserScan&)> on_scan;
  std::function<void(double stamp_s, const cv::Mat& grey)> on_image;
  std::function<void(const PlanarPoseStamped&)> on_initial_pose;
};

struct DdsInputCounters {
  std::uint64_t received = 0;
  std::uint64_t accepted = 0;
  std::uint64_t dropped = 0;
  std::string last_drop_reason;  // the validation message of the last drop
  std::uint64_t clock_steps = 0;  // the sender's clock stepped back (clock_step_messages)
};

class DdsInputs {
 public:
  static core::Result<DdsInputs> Create(const DdsParticipant& participant,
                                        const DdsInputsOptions& options,
                                        DdsInputCallbacks callbacks);
  DdsInputs(DdsInputs&&) noexcept;
  DdsInputs& operator=(DdsInputs&&) noexcept;
  ~DdsInputs();

  // Waits up to `timeout` for data on any input, then takes, validates and
  // delivers everything available (callbacks run inside, on this thread). Returns the number of messages accepted; an error
  // only for a failing DDS call.
  core::Result<int> Poll(std::chrono::milliseconds timeout);

  const DdsInputCounters& counters(DdsInput input) const;
  // How many writers each subscribed input is matched with.
  std::uint32_t MatchedWriters(DdsInput input) const;

 private:
  struct Impl;
  explicit DdsInputs(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_DDS_INPUTS_H_
