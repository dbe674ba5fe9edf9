#include "groundline/service/service_config.h"

#include <cmath>

#include "groundline/core/yaml_fields.h"

namespace groundline::service {

core::Status ServiceConfig::Validate() const {
  if (replay_dataset.empty()) {
    return core::Status::Error("inputs.replay.dataset: expected a dataset directory, got nothing");
  }
  if (!(std::isfinite(replay_speed) && replay_speed >= 0.0 && replay_speed <= 1000.0)) {
    return core::Status::Error(
        "inputs.replay.speed: expected 0 (as fast as possible) or a factor "
        "in (0, 1000], got " +
        std::to_string(replay_speed));
  }
  if (replay_loops < 1 || replay_loops > 100000) {
    return core::Status::Error("inputs.replay.loops: expected 1..100000, got " +
                               std::to_string(replay_loops));
  }
  for (std::size_t i = 0; i < faults.size(); ++i) {
    const InjectedFault& f = faults[i];
    const std::string at = "inputs.replay.faults[" + std::to_string(i) + "]";
    using Sensor = InjectedFault::Sensor;
    const bool known =
        f.sensor == Sensor::kCamera
            ? (f.kind == "silent" || f.kind == "blackout" || f.kind == "corrupt")
        : f.sensor == Sensor::kLidar ? f.kind == "silent"
        : f.sensor == Sensor::kClock
            ? f.kind == "jump"
            : (f.kind == "nan" || f.kind == "frozen" || f.kind == "reorder" ||
               f.kind == "duplicate");
    if (!known) {
      return core::Status::Error(at +
                                 ".kind: expected camera silent|blackout|corrupt, lidar "
                                 "silent, odometry nan|frozen|reorder|duplicate, clock jump, got '" +
                                 f.kind + "'");
    }
    if (f.sensor == Sensor::kClock) {
      if (!(std::isfinite(f.from_s) && f.from_s >= 0.0 && std::isfinite(f.by_s) &&
            f.by_s != 0.0 && std::abs(f.by_s) <= 1e7)) {
        return core::Status::Error(at + ": expected from_s >= 0 and a finite by_s != 0 [s]");
      }
    } else if (!(std::isfinite(f.from_s) && std::isfinite(f.to_s) && f.from_s >= 0.0 &&
                 f.to_s > f.from_s)) {
      return core::Status::Error(at + ": expected 0 <= from_s < to_s");
    }
  }
  if (!camera_uri.empty() && replay_speed == 0.0) {
    return core::Status::Error(
        "inputs.camera.uri: a camera delivers frames at its own pace: set inputs.replay.speed "
        "> 0 (the replay's odometry and scans then follow the wall clock too)");
  }
  if (preset != "fusion" && preset != "lines" && preset != "odometry" && preset != "lidar") {
    return core::Status::Error(
        "localizer.preset: expected fusion, lines, odometry or lidar, got '" + preset + "'");
  }
  if (initial_pose) {
    for (double v : *initial_pose) {
      if (!std::isfinite(v) || std::abs(v) > 1e6) {
        return core::Status::Error(
            "start.initial_pose: expected three finite numbers [x_m, y_m, yaw_deg] within 1e6");
      }
    }
  }
  if (relocalize && preset != "fusion" && preset != "lines") {
    return core::Status::Error("start.relocalize: needs the lines or fusion preset (an atlas)");
  }
  if (output_dir.empty())
    return core::Status::Error("output.dir: expected a directory, got nothing");
  if (http_port < 0 || http_port > 65535) {
    return core::Status::Error("http.port: expected 0..65535, got " + std::to_string(http_port));
  }
  if (camera_queue_depth < 1 || camera_queue_depth > 64) {
    return core::Status::Error("queues.camera: expected 1..64 frames, got " +
                               std::to_string(camera_queue_depth));
  }
  if (!(std::isfinite(max_frame_wait_s) && max_frame_wait_s >= 0.0 && max_frame_wait_s <= 1.0)) {
    return core::Status::Error("queues.max_frame_wait_s: expected 0..1 s, got " +
                               std::to_string(max_frame_wait_s));
  }
  return core::Status::Ok();
}

core::Result<ServiceConfig> ReadServiceConfig(const std::filesystem::path& path) {
  core::Result<YAML::Node> loaded = core::internal::LoadYamlFile(path);
  if (!loaded.ok()) return loaded.status();
  const YAML::Node& root = *loaded;
  core::internal::YamlFields y(path.string());
  ServiceConfig c;
  if (!y.ExpectMap(root, "")) return y.status();
  y.CheckKeys(root, "", {"inputs", "localizer", "start", "output", "http", "queues"});
  const YAML::Node inputs = y.Child(root, "", "inputs");
  if (inputs && y.ExpectMap(inputs, "inputs")) {
    y.CheckKeys(inputs, "inputs", {"replay", "camera"});
    if (const YAML::Node camera = inputs["camera"];
        camera && y.ExpectMap(camera, "inputs.camera")) {
      y.CheckKeys(camera, "inputs.camera", {"uri"});
      c.camera_uri = y.Text(camera, "inputs.camera", "uri");
    }
    const YAML::Node replay = y.Child(inputs, "inputs", "replay");
    if (replay && y.ExpectMap(replay, "inputs.replay")) {
      y.CheckKeys(replay, "inputs.replay", {"dataset", "speed", "loops", "faults"});
      c.replay_dataset = y.Text(replay, "inputs.replay", "dataset");
      if (replay["speed"]) c.replay_speed = y.Number(replay, "inputs.replay", "speed");
      if (replay["loops"])
        c.replay_loops = static_cast<int>(y.Integer(replay, "inputs.replay", "loops"));
      if (const YAML::Node faults = replay["faults"];
          faults && y.ExpectSequence(faults, "inputs.replay.faults")) {
        for (std::size_t i = 0; i < faults.size() && y.ok(); ++i) {
          const std::string at = "inputs.replay.faults[" + std::to_string(i) + "]";
          if (!y.ExpectMap(faults[i], at)) break;
          y.CheckKeys(faults[i], at, {"sensor", "kind", "from_s", "to_s", "by_s"});
          InjectedFault f;
          const std::string sensor = y.Text(faults[i], at, "sensor");
          if (sensor == "camera") {
            f.sensor = InjectedFault::Sensor::kCamera;
          } else if (sensor == "lidar") {
            f.sensor = InjectedFault::Sensor::kLidar;
          } else if (sensor == "odometry") {
            f.sensor = InjectedFault::Sensor::kOdometry;
          } else if (sensor == "clock") {
            f.sensor = InjectedFault::Sensor::kClock;
          } else if (y.ok()) {
            y.Fail(faults[i]["sensor"], at + ".sensor", "camera, lidar, odometry or clock",
                   sensor);
          }
          f.kind = y.Text(faults[i], at, "kind");
          f.from_s = y.Number(faults[i], at, "from_s");
          if (f.sensor == InjectedFault::Sensor::kClock) {
            f.by_s = y.Number(faults[i], at, "by_s");
          } else {
            f.to_s = y.Number(faults[i], at, "to_s");
          }
          c.faults.push_back(f);
        }
      }
    }
  }
  if (const YAML::Node n = y.Child(root, "", "localizer", false);
      n && y.ExpectMap(n, "localizer")) {
    y.CheckKeys(n, "localizer", {"preset", "atlas"});
    if (n["preset"]) c.preset = y.Text(n, "localizer", "preset");
    if (n["atlas"]) c.atlas = y.Text(n, "localizer", "atlas");
  }
  if (const YAML::Node n = y.Child(root, "", "start", false); n && y.ExpectMap(n, "start")) {
    y.CheckKeys(n, "start", {"initial_pose", "relocalize", "resume"});
    if (const YAML::Node p = n["initial_pose"]) {
      if (y.ExpectSequence(p, "start.initial_pose")) {
        if (p.size() != 3) {
          y.Fail(p, "start.initial_pose", "three numbers [x_m, y_m, yaw_deg]",
                 std::to_string(p.size()) + " values");
        } else {
          c.initial_pose = std::array<double, 3>{y.NumberAt(p[0], "start.initial_pose[0]"),
                                                 y.NumberAt(p[1], "start.initial_pose[1]"),
                                                 y.NumberAt(p[2], "start.initial_pose[2]")};
        }
      }
    }
    if (n["relocalize"]) c.relocalize = y.BoolAt(n["relocalize"], "start.relocalize");
    if (n["resume"]) c.resume = y.BoolAt(n["resume"], "start.resume");
  }
  const YAML::Node output = y.Child(root, "", "output");
  if (output && y.ExpectMap(output, "output")) {
    y.CheckKeys(output, "output", {"dir"});
    c.output_dir = y.Text(output, "output", "dir");
  }
  if (const YAML::Node n = y.Child(root, "", "http", false); n && y.ExpectMap(n, "http")) {
    y.CheckKeys(n, "http", {"enabled", "address", "port"});
    if (n["enabled"]) c.http_enabled = y.BoolAt(n["enabled"], "http.enabled");
    if (n["address"]) c.http_address = y.Text(n, "http", "address");
    if (n["port"]) c.http_port = static_cast<int>(y.Integer(n, "http", "port"));
  }
  if (const YAML::Node n = y.Child(root, "", "queues", false); n && y.ExpectMap(n, "queues")) {
    y.CheckKeys(n, "queues", {"camera", "max_frame_wait_s"});
    if (n["camera"]) c.camera_queue_depth = static_cast<int>(y.Integer(n, "queues", "camera"));
    if (n["max_frame_wait_s"]) c.max_frame_wait_s = y.Number(n, "queues", "max_frame_wait_s");
  }
  if (!y.ok()) return y.status();
  // Relative paths are relative to the config file's directory.
  const std::filesystem::path base = path.has_parent_path() ? path.parent_path() : ".";
  for (std::string* p : {&c.replay_dataset, &c.atlas, &c.output_dir}) {
    if (!p->empty() && std::filesystem::path(*p).is_relative()) *p = (base / *p).string();
  }
  if (core::Status s = c.Validate(); !s.ok()) return s.WithContext(path.string());
  return c;
}

}  // namespace groundline::service
