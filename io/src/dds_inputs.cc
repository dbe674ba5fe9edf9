#include "groundline/io/dds_inputs.h"

#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

#include "groundline/io/dds_convert_sensors.h"
#include "groundline/io/dds_pubsub.h"

namespace groundline::io {

const char* DdsInputName(DdsInput input) {
  switch (input) {
    case DdsInput::kOdometry:
      return "odometry";
    case DdsInput::kJointState:
      return "joint_state";
    case DdsInput::kScan:
      return "scan";
    case DdsInput::kImage:
      return "image";
    case DdsInput::kInitialPose:
      return "initial_pose";
  }
  return "?";
}

namespace {

// The ROS 2 type of each input, for messages.
const char* RosTypeOf(DdsInput input) {
  switch (input) {
    case DdsInput::kOdometry:
      return "nav_msgs/Odometry";
    case DdsInput::kJointState:
      return "sensor_msgs/JointState";
    case DdsInput::kScan:
      return "sensor_msgs/LaserScan";
    case DdsInput::kImage:
      return "sensor_msgs/Image";
    case DdsInput::kInitialPose:
      return "geometry_msgs/PoseWithCovarianceStamped";
  }
  return "?";
}

}  // namespace

core::Status DdsInputsOptions::Validate() const {
  if (core::Status s = stamp_window.Validate(); !s.ok()) return s.WithContext("DdsInputsOptions");
  if (clock_step_messages < 2) {
    return core::Status::Error("DdsInputsOptions: clock_step_messages: expected >= 2, got " +
                               std::to_string(clock_step_messages));
  }
  const std::string* topics[] = {&odometry_topic, &joint_state_topic, &scan_topic, &image_topic,
                                 &initial_pose_topic};
  bool any = false;
  for (const std::string* t : topics) {
    if (t->empty()) continue;
    any = true;
    if (t->rfind("rt/", 0) != 0) {
      return core::Status::Error("DdsInputsOptions: topic '" + *t +
                                 "' must start with 'rt/' (ROS 2 topic prefix) or be empty");
    }
  }
  if (!any) return core::Status::Error("DdsInputsOptions: every topic is empty");
  if (left_wheel_joint.empty() || right_wheel_joint.empty() ||
      left_wheel_joint == right_wheel_joint) {
    return core::Status::Error(
        "DdsInputsOptions: wheel joint names must be distinct, non-empty (got '" +
        left_wheel_joint + "', '" + right_wheel_joint + "')");
  }
  return core::Status::Ok();
}

struct DdsInputs::Impl {
  DdsInputsOptions options;
  DdsInputCallbacks callbacks;
  std::optional<DdsSubscriber<RosOdometry>> odometry;
  std::optional<DdsSubscriber<RosJointState>> joints;
  std::optional<DdsSubscriber<RosLaserScan>> scan;
  std::optional<DdsSubscriber<RosImage>> image;
  std::optional<DdsSubscriber<RosPoseWithCovarianceStamped>> initial_pose;
  std::optional<DdsWaitSet> waitset;  // after the subscribers: destroyed first
  std::array<DdsInputCounters, kNumDdsInputs> counters;
  std::array<std::optional<double>, kNumDdsInputs> last_stamp_s;
  // Per topic: the consecutive messages older than the newest accepted.
  std::array<std::vector<double>, kNumDdsInputs> older_run;
  std::optional<double> newest_stamp_s;
  std::optional<std::pair<double, double>> last_wheel_angles_rad;
  // Accepted messages of one Poll, converted, waiting to be merged by stamp.
  struct Pending {
    double stamp_s;
    std::function<void()> deliver;
  };
  std::vector<Pending> pending;

  DdsCheck CheckFor(const std::string& frame) const {
    DdsCheck check;
    check.frame_id = frame;
    check.window = options.stamp_window;
    switch (options.stamp_reference) {
      case StampReference::kNone:
        break;
      case StampReference::kWallClock:
        check.reference_s =
            std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
                .count();
        break;
      case StampReference::kNewest:
        check.reference_s = newest_stamp_s;
        break;
    }
    return check;
  }

  // Validation result plus the per-topic time order; counts the message.
  bool Admit(DdsInput which, const RosHeader& header, const core::Status& valid) {
    DdsInputCounters& c = counters[static_cast<int>(which)];
    ++c.received;
    core::Status s = valid;
    if (which == DdsInput::kInitialPose) {
      // A command, not a stream: each one stands alone (an unset stamp, 0,
      // may repeat; the localizer judges its time), and it does not move the
      // sensors' newest stamp.
      if (!s.ok()) {
        ++c.dropped;
        c.last_drop_reason = s.message();
        return false;
      }
      ++c.accepted;
      return true;
    }
    const double stamp_s = FromRosTime(header.stamp);
    std::optional<double>& last = last_stamp_s[static_cast<int>(which)];
    std::vector<double>& run = older_run[static_cast<int>(which)];
    if (s.ok() && last && stamp_s <= *last) {
      if (!run.empty() && !(stamp_s > run.back())) run.clear();
      run.push_back(stamp_s);
      if (static_cast<int>(run.size()) >= options.clock_step_messages) {
        ++c.clock_steps;  // the sender's clock stepped back: its order restarts here
        last.reset();
      }
    } else if (s.ok()) {
      run.clear();
    }
    if (s.ok() && last && stamp_s <= *last) {
      s = core::Status::Error(std::string(RosTypeOf(which)) + ": field 'header.stamp': " +
                              std::to_string(stamp_s) + " s is not after the previous " +
                              std::to_string(*last) + " s (messages must arrive in time order)");
    }
    if (!s.ok()) {
      ++c.dropped;
      c.last_drop_reason = s.message();
      return false;
    }
    ++c.accepted;
    if (!last) run.clear();
    last = stamp_s;
    if (!newest_stamp_s || stamp_s > *newest_stamp_s) newest_stamp_s = stamp_s;
    return true;
  }

  void OnJointState(const RosJointState& m) {
    const std::string& l = options.left_wheel_joint;
    const std::string& r = options.right_wheel_joint;
    if (!Admit(DdsInput::kJointState, m.header, ValidateJointState(m, CheckFor(""), {l, r}))) {
      return;
    }
    double left = 0.0, right = 0.0;
    for (std::uint32_t i = 0; i < m.name._length; ++i) {
      if (m.name._buffer[i] == nullptr) continue;
      if (l == m.name._buffer[i]) left = m.position._buffer[i];
      if (r == m.name._buffer[i]) right = m.position._buffer[i];
    }
    core::WheelEncoderReading reading;
    reading.stamp_s = FromRosTime(m.header.stamp);
    if (last_wheel_angles_rad) {
      reading.left_delta_rad = left - last_wheel_angles_rad->first;
      reading.right_delta_rad = right - last_wheel_angles_rad->second;
    }
    last_wheel_angles_rad = std::make_pair(left, right);
    pending.push_back({reading.stamp_s, [this, reading] { callbacks.on_wheels(reading); }});
  }
};

DdsInputs::DdsInputs(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
DdsInputs::DdsInputs(DdsInputs&&) noexcept = default;
DdsInputs& DdsInputs::operator=(DdsInputs&&) noexcept = default;
DdsInputs::~DdsInputs() = default;

namespace {

template <typename T>
core::Status Subscribe(const DdsParticipant& participant, const std::string& topic, bool wanted,
                       QosPreset qos, std::optional<DdsSubscriber<T>>* out) {
  if (topic.empty() || !wanted) return core::Status::Ok();
  core::Result<DdsSubscriber<T>> sub = DdsSubscriber<T>::Create(participant, topic, qos);
  if (!sub.ok()) return sub.status();
  out->emplace(std::move(*sub));
  return core::Status::Ok();
}

}  // namespace

core::Result<DdsInputs> DdsInputs::Create(const DdsParticipant& participant,
                                          const DdsInputsOptions& options,
                                          DdsInputCallbacks callbacks) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->callbacks = std::move(callbacks);
  const DdsInputCallbacks& cb = impl->callbacks;
  // Best-effort readers match both best-effort and reliable sensor writers.
  core::Status s = Subscribe(participant, options.odometry_topic, bool(cb.on_odometry),
                             options.sensor_qos, &impl->odometry);
  if (s.ok()) {
    s = Subscribe(participant, options.joint_state_topic, bool(cb.on_wheels), options.sensor_qos,
                  &impl->joints);
  }
  if (s.ok()) {
    s = Subscribe(participant, options.scan_topic, bool(cb.on_scan), options.sensor_qos,
                  &impl->scan);
  }
  if (s.ok()) {
    s = Subscribe(participant, options.image_topic, bool(cb.on_image), options.sensor_qos,
                  &impl->image);
  }
  if (s.ok()) {
    // rviz's "2D Pose Estimate" publishes reliable, volatile.
    s = Subscribe(participant, options.initial_pose_topic, bool(cb.on_initial_pose),
                  QosPreset::kDefault, &impl->initial_pose);
  }
  if (!s.ok()) return s;
  core::Result<DdsWaitSet> ws = DdsWaitSet::Create(participant);
  if (!ws.ok()) return ws.status();
  impl->waitset.emplace(std::move(*ws));
  const DdsEntity* readers[] = {impl->odometry ? &impl->odometry->reader() : nullptr,
                                impl->joints ? &impl->joints->reader() : nullptr,
                                impl->scan ? &impl->scan->reader() : nullptr,
                                impl->image ? &impl->image->reader() : nullptr,
                                impl->initial_pose ? &impl->initial_pose->reader() : nullptr};
  bool any = false;
  for (const DdsEntity* r : readers) {
    if (r == nullptr) continue;
    any = true;
    if (core::Status a = impl->waitset->Attach(*r); !a.ok()) return a;
  }
  if (!any) return core::Status::Error("DdsInputs: no topic has both a name and a callback");
  return DdsInputs(std::move(impl));
}

core::Result<int> DdsInputs::Poll(std::chrono::milliseconds timeout) {
  Impl& d = *impl_;
  d.pending.clear();
  core::Result<bool> ready = d.waitset->Wait(timeout);
  if (!ready.ok()) return ready.status();
  const std::uint64_t before = [&] {
    std::uint64_t n = 0;
    for (const DdsInputCounters& c : d.counters) n += c.accepted;
    return n;
  }();
  if (d.odometry) {
    core::Result<int> n = d.odometry->Take([&](const RosOdometry& m) {
      if (d.Admit(DdsInput::kOdometry, m.header,
                  ValidateOdometry(m, d.CheckFor(d.options.odom_frame), d.options.base_frame))) {
        d.pending.push_back({FromRosTime(m.header.stamp),
                             [&d, o = FromOdometry(m)] { d.callbacks.on_odometry(o); }});
      }
    });
    if (!n.ok()) return n.status();
  }
  if (d.joints) {
    core::Result<int> n = d.joints->Take([&](const RosJointState& m) { d.OnJointState(m); });
    if (!n.ok()) return n.status();
  }
  if (d.scan) {
    core::Result<int> n = d.scan->Take([&](const RosLaserScan& m) {
      if (d.Admit(DdsInput::kScan, m.header,
                  ValidateLaserScan(m, d.CheckFor(d.options.lidar_frame)))) {
        d.pending.push_back({FromRosTime(m.header.stamp),
                             [&d, scan = FromLaserScan(m)] { d.callbacks.on_scan(scan); }});
      }
    });
    if (!n.ok()) return n.status();
  }
  if (d.image) {
    core::Result<int> n = d.image->Take([&](const RosImage& m) {
      if (d.Admit(DdsInput::kImage, m.header,
                  ValidateImage(m, d.CheckFor(d.options.camera_frame)))) {
        core::Result<cv::Mat> grey = FromMono8Image(m);
        const double stamp_s = FromRosTime(m.header.stamp);
        if (grey.ok()) {
          d.pending.push_back({stamp_s, [&d, stamp_s, img = std::move(*grey)] {
                                 d.callbacks.on_image(stamp_s, img);
                               }});
        }
      }
    });
    if (!n.ok()) return n.status();
  }
  if (d.initial_pose) {
    core::Result<int> n = d.initial_pose->Take([&](const RosPoseWithCovarianceStamped& m) {
      // An initial pose is a command, not a sensor stream: no stamp window.
      DdsCheck check;
      check.frame_id = d.options.map_frame;
      if (d.Admit(DdsInput::kInitialPose, m.header, ValidatePoseWithCovarianceStamped(m, check))) {
        d.callbacks.on_initial_pose(FromPoseWithCovarianceStamped(m));
      }
    });
    if (!n.ok()) return n.status();
  }
  // Sensor data of this Poll in stamp order (stable: ties keep topic order).
  std::stable_sort(
      d.pending.begin(), d.pending.end(),
      [](const Impl::Pending& a, const Impl::Pending& b) { return a.stamp_s < b.stamp_s; });
  for (const Impl::Pending& p : d.pending) p.deliver();
  d.pending.clear();
  std::uint64_t after = 0;
  for (const DdsInputCounters& c : d.counters) after += c.accepted;
  return static_cast<int>(after - before);
}

const DdsInputCounters& DdsInputs::counters(DdsInput input) const {
  return impl_->counters[static_cast<int>(input)];
}

std::uint32_t DdsInputs::MatchedWriters(DdsInput input) const {
  const Impl& d = *impl_;
  const DdsEntity* reader = nullptr;
  switch (input) {
    case DdsInput::kOdometry:
      reader = d.odometry ? &d.odometry->reader() : nullptr;
      break;
    case DdsInput::kJointState:
      reader = d.joints ? &d.joints->reader() : nullptr;
      break;
    case DdsInput::kScan:
      reader = d.scan ? &d.scan->reader() : nullptr;
      break;
    case DdsInput::kImage:
      reader = d.image ? &d.image->reader() : nullptr;
      break;
    case DdsInput::kInitialPose:
      reader = d.initial_pose ? &d.initial_pose->reader() : nullptr;
      break;
  }
  if (reader == nullptr) return 0;
  core::Result<std::uint32_t> n = io::MatchedWriters(*reader);
  return n.ok() ? *n : 0;
}

}  // namespace groundline::io
