// The service's DDS edge: ROS 2 topics in (io::DdsInputs -> the estimator's
// event queue, in arrival order, the same path the replay feeds) and out
// (io::DdsOutputs: pose, map -> odom, diagnostics).
#include <cstdio>

#include "service_impl.h"

namespace groundline::service {
namespace {

std::string TopicPrefix(const std::string& ros_namespace) {
  return ros_namespace.empty() ? std::string("rt/") : "rt/" + ros_namespace + "/";
}

std::string Fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

}  // namespace

core::Status Service::Impl::CreateDds() {
  const DdsInputConfig& in = config.dds_inputs;
  const DdsOutputConfig& out = config.dds_outputs;
  if (!in.enabled && !out.enabled) return core::Status::Ok();
  core::Result<io::DdsParticipant> participant = io::DdsParticipant::Create();
  if (!participant.ok()) return participant.status().WithContext("DDS (inputs.dds, output.dds)");
  dds.emplace(std::move(participant).value());
  if (in.enabled) {
    const std::string prefix = TopicPrefix(in.ros_namespace);
    io::DdsInputsOptions o;
    o.odometry_topic = in.odometry == "odom" ? prefix + "odom" : "";
    o.joint_state_topic = in.odometry == "joint_states" ? prefix + "joint_states" : "";
    o.scan_topic = in.scan ? prefix + "scan" : "";
    o.image_topic = in.image ? prefix + "camera/image_raw" : "";
    o.initial_pose_topic = in.initial_pose ? prefix + "initialpose" : "";
    o.map_frame = config.dds_outputs.map_frame;
    o.odom_frame = in.odom_frame;
    o.base_frame = in.base_frame;
    o.lidar_frame = in.lidar_frame;
    o.camera_frame = in.camera_frame;
    o.left_wheel_joint = in.left_wheel_joint;
    o.right_wheel_joint = in.right_wheel_joint;
    o.stamp_reference = in.stamp_check == "wall"     ? io::StampReference::kWallClock
                        : in.stamp_check == "newest" ? io::StampReference::kNewest
                                                     : io::StampReference::kNone;
    o.sensor_qos = in.qos == "lossless" ? io::QosPreset::kLossless : io::QosPreset::kSensorData;
    io::DdsInputCallbacks cb;
    // Consecutive odom poses -> the wheel reading that drives their arc.
    cb.on_odometry = [this](const io::PlanarOdometry& odometry) {
      const core::SE2 increment =
          dds_last_T_odom_base ? dds_last_T_odom_base->Between(odometry.T_odom_base) : core::SE2();
      dds_last_T_odom_base = odometry.T_odom_base;
      const loc::WheelAngleIncrement wheels = loc::WheelsFromIncrement(drive, increment);
      EstimatorEvent event;
      event.wheel = {odometry.stamp_s, wheels.left_rad, wheels.right_rad};
      event.T_odom_base = odometry.T_odom_base;
      replay_now_s.store(odometry.stamp_s);
      PushEvent(std::move(event));
    };
    cb.on_wheels = [this](const core::WheelEncoderReading& reading) {
      EstimatorEvent event;
      event.wheel = reading;
      replay_now_s.store(reading.stamp_s);
      PushEvent(std::move(event));
    };
    cb.on_scan = [this](const core::LaserScan& scan) {
      EstimatorEvent event;
      event.kind = EstimatorEvent::Kind::kScan;
      event.scan = scan;
      PushEvent(std::move(event));
    };
    cb.on_image = [this](double stamp_s, const cv::Mat& grey) {
      FrameJob job;
      job.stamp_s = stamp_s;
      job.grey = grey;
      job.arrived = Clock::now();
      PushFrame(std::move(job));
    };
    cb.on_initial_pose = [this](const io::PlanarPoseStamped& pose) {
      EstimatorEvent event;
      event.kind = EstimatorEvent::Kind::kInitialPose;
      event.initial_pose = pose;
      PushEvent(std::move(event));
    };
    core::Result<io::DdsInputs> inputs = io::DdsInputs::Create(*dds, o, std::move(cb));
    if (!inputs.ok()) return inputs.status().WithContext("inputs.dds");
    dds_inputs.emplace(std::move(inputs).value());
  }
  if (out.enabled) {
    const std::string prefix = TopicPrefix(out.ros_namespace);
    io::DdsOutputsOptions o;
    o.pose_topic = out.pose ? prefix + "groundline/pose" : "";
    o.tf_topic = out.tf ? prefix + "tf" : "";
    o.diagnostics_topic = out.diagnostics ? prefix + "diagnostics" : "";
    o.map_frame = out.map_frame;
    o.odom_frame = out.odom_frame;
    core::Result<io::DdsOutputs> outputs = io::DdsOutputs::Create(*dds, o);
    if (!outputs.ok()) return outputs.status().WithContext("output.dds");
    dds_outputs.emplace(std::move(outputs).value());
  }
  return core::Status::Ok();
}

void Service::Impl::DdsInputLoop(const std::atomic<bool>& stop) {
  Clock::time_point matched_at{};
  while (!stop.load()) {
    core::Result<int> polled = dds_inputs->Poll(std::chrono::milliseconds(50));
    const bool refresh_matches = Clock::now() - matched_at > std::chrono::seconds(1);
    if (refresh_matches) matched_at = Clock::now();
    {
      std::lock_guard<std::mutex> lock(status_mutex);
      if (!polled.ok()) {
        ++dds_poll_errors;
        dds_last_error = polled.message();
      }
      for (int i = 0; i < io::kNumDdsInputs; ++i) {
        const auto input = static_cast<io::DdsInput>(i);
        dds_counters[i] = dds_inputs->counters(input);
        if (refresh_matches) dds_matched[i] = dds_inputs->MatchedWriters(input);
      }
    }
    // A failing DDS call is reported, never fatal; do not spin on it.
    if (!polled.ok()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // What the readers hold already (acknowledged to its writers) is taken and
  // passed on before the inputs close.
  const auto received = [this] {
    std::uint64_t n = 0;
    for (int i = 0; i < io::kNumDdsInputs; ++i)
      n += dds_inputs->counters(static_cast<io::DdsInput>(i)).received;
    return n;
  };
  for (std::uint64_t before = received();;) {
    if (!dds_inputs->Poll(std::chrono::milliseconds(0)).ok()) break;
    const std::uint64_t after = received();
    if (after == before) break;
    before = after;
  }
  std::lock_guard<std::mutex> lock(status_mutex);
  for (int i = 0; i < io::kNumDdsInputs; ++i)
    dds_counters[i] = dds_inputs->counters(static_cast<io::DdsInput>(i));
}

void Service::Impl::PublishDds(const core::SE2* T_odom_base,
                               const std::optional<loc::KeyframeOutput>& keyframe) {
  if (!dds_outputs) return;
  const DdsOutputConfig& out = config.dds_outputs;
  const auto count = [this](const core::Status& s, long* published) {
    if (s.ok()) {
      ++*published;
    } else {
      ++dds_write_errors;
      dds_last_error = s.message();
    }
  };
  if (out.tf && T_odom_base) {
    // T_map_odom = T_map_base * T_odom_base^-1 at the reading (nav2 AMCL's
    // map -> odom), post-dated by the transform tolerance.
    count(dds_outputs->PublishMapToOdom(pose.stamp_s + out.transform_tolerance_s,
                                        pose.T_map_base * T_odom_base->Inverse()),
          &dds_tf_out);
  }
  if (out.pose && keyframe) {
    count(dds_outputs->PublishPose(
              keyframe->pose.stamp_s, keyframe->pose.T_map_base,
              keyframe->has_covariance ? keyframe->pose.covariance : pose.covariance),
          &dds_poses_out);
  }
  if (out.diagnostics && Clock::now() - dds_last_diagnostics >=
                             std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(out.diagnostics_period_s))) {
    PublishDiagnostics();
  }
}

void Service::Impl::PublishDiagnostics() {
  const Clock::time_point now = Clock::now();
  const double period_s = dds_last_diagnostics == Clock::time_point{}
                              ? 0.0
                              : std::chrono::duration<double>(now - dds_last_diagnostics).count();
  dds_last_diagnostics = now;
  const loc::LocalizerCounters& c = counters;
  const loc::LocalizerCounters& b = dds_diag_counters;
  const auto rate = [period_s](long now_count, long before) {
    return period_s > 0.0 ? Fixed(static_cast<double>(now_count - before) / period_s, 1) : "-";
  };
  const long dropped = c.WheelReadingsDropped() + c.scans_dropped_bad +
                       c.scans_dropped_out_of_order + c.frames_dropped_late;
  const long dropped_before = b.WheelReadingsDropped() + b.scans_dropped_bad +
                              b.scans_dropped_out_of_order + b.frames_dropped_late;
  std::uint64_t dds_dropped = 0;
  for (const io::DdsInputCounters& d : dds_counters) dds_dropped += d.dropped;

  const nlohmann::ordered_json& k = last_keyframe;
  const std::string degraded =
      k.contains("sensors") ? k["sensors"].value("degraded_mode", std::string()) : std::string();
  io::DiagnosticEntry estimate;
  estimate.name = "groundline: localizer";
  estimate.hardware_id = "groundline";
  estimate.level = !localizer->started()                    ? io::DiagnosticLevel::kWarn
                   : degraded.empty() || degraded == "full" ? io::DiagnosticLevel::kOk
                                                            : io::DiagnosticLevel::kWarn;
  estimate.message = !localizer->started() ? "waiting for a start pose"
                     : degraded.empty()    ? "running"
                                           : degraded;
  const auto last = [&k](const char* key, int digits) {
    return k.contains(key) && k[key].is_number() ? Fixed(k[key].get<double>(), digits)
                                                 : std::string("-");
  };
  estimate.values = {
      {"mode", loc::ModeName(localizer->options())},
      {"keyframes", std::to_string(c.keyframes)},
      {"reinitializations", std::to_string(c.reinitializations)},
      {"lines per frame (last keyframe)", last("lines_used", 0)},
      {"lines rejected (last keyframe)", last("lines_rejected", 0)},
      {"lidar degenerate (last keyframe)",
       k.contains("lidar_degenerate") ? k["lidar_degenerate"].dump() : std::string("-")},
      {"walls used (last keyframe)", last("walls_used", 0)},
      {"solve time ms (last keyframe)", last("solve_ms", 2)},
      {"latency ms median", Fixed(Percentile(latency_ms, 0.5), 2)},
      {"sigma x m", Fixed(std::sqrt(std::max(0.0, pose.covariance(0, 0))), 4)},
      {"sigma y m", Fixed(std::sqrt(std::max(0.0, pose.covariance(1, 1))), 4)}};
  io::DiagnosticEntry inputs;
  inputs.name = "groundline: inputs";
  inputs.hardware_id = "groundline";
  const bool dropping = dropped > dropped_before || camera_dropped.load() > 0 || dds_dropped > 0;
  inputs.level = dropping ? io::DiagnosticLevel::kWarn : io::DiagnosticLevel::kOk;
  inputs.message = dropping ? "messages dropped (counted)" : "ok";
  inputs.values = {
      {"odometry rate hz", rate(c.wheel_readings, b.wheel_readings)},
      {"scan rate hz", rate(c.scans, b.scans)},
      {"frame rate hz", rate(c.frames, b.frames)},
      {"readings dropped", std::to_string(c.WheelReadingsDropped())},
      {"scans dropped", std::to_string(c.scans_dropped_bad + c.scans_dropped_out_of_order)},
      {"frames dropped (queue full)", std::to_string(camera_dropped.load())},
      {"frames dropped (late)", std::to_string(c.frames_dropped_late)}};
  if (dds_inputs) {
    for (int i = 0; i < io::kNumDdsInputs; ++i) {
      const io::DdsInputCounters& d = dds_counters[i];
      if (d.received == 0 && dds_matched[i] == 0) continue;
      const std::string name = std::string("dds ") + io::DdsInputName(static_cast<io::DdsInput>(i));
      inputs.values.push_back({name + " received", std::to_string(d.received)});
      inputs.values.push_back({name + " dropped", std::to_string(d.dropped)});
      if (d.dropped > 0) inputs.values.push_back({name + " last drop", d.last_drop_reason});
    }
  }
  dds_diag_counters = counters;
  const core::Status s = dds_outputs->PublishDiagnostics(pose.stamp_s, {estimate, inputs});
  if (s.ok()) {
    ++dds_diagnostics_out;
  } else {
    ++dds_write_errors;
    dds_last_error = s.message();
  }
}

nlohmann::ordered_json Service::Impl::DdsJson() const {
  nlohmann::ordered_json j;
  j["domain_id"] = dds ? dds->domain_id() : 0;
  if (dds_inputs) {
    nlohmann::ordered_json inputs;
    for (int i = 0; i < io::kNumDdsInputs; ++i) {
      const io::DdsInputCounters& d = dds_counters[i];
      inputs[io::DdsInputName(static_cast<io::DdsInput>(i))] = {
          {"received", d.received},
          {"accepted", d.accepted},
          {"dropped", d.dropped},
          {"last_drop_reason", d.last_drop_reason},
          {"matched_writers", dds_matched[i]}};
    }
    j["inputs"] = std::move(inputs);
    j["initial_poses"] = {{"applied", initial_poses_applied},
                          {"refused", initial_poses_refused},
                          {"last_error", initial_pose_last_error}};
    j["poll_errors"] = dds_poll_errors;
  }
  if (dds_outputs) {
    j["outputs"] = {{"poses", dds_poses_out},
                    {"tf", dds_tf_out},
                    {"diagnostics", dds_diagnostics_out},
                    {"write_errors", dds_write_errors}};
  }
  j["last_error"] = dds_last_error;
  return j;
}

}  // namespace groundline::service
