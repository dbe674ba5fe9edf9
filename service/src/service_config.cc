#include "groundline/service/service_config.h"

#include <cmath>

#include "groundline/core/yaml_fields.h"
#include "groundline/perception/bev_remap.h"

namespace groundline::service {
namespace {

// An optional text key that must be one of `allowed` (the line named on error).
void ReadChoice(core::internal::YamlFields& y, const YAML::Node& map, const std::string& path,
                const char* key, std::initializer_list<const char*> allowed, std::string* out) {
  if (!map[key] || !y.ok()) return;
  const std::string value = y.Text(map, path, key, true);
  std::string expected;
  for (const char* a : allowed) {
    if (value == a) {
      *out = value;
      return;
    }
    expected += (expected.empty() ? "" : " | ") + std::string(a);
  }
  if (y.ok()) y.Fail(map[key], path + "." + key, expected, value);
}

void ReadBool(core::internal::YamlFields& y, const YAML::Node& map, const std::string& path,
              const char* key, bool* out) {
  if (map[key] && y.ok()) *out = y.BoolAt(map[key], path + "." + key);
}

void ReadText(core::internal::YamlFields& y, const YAML::Node& map, const std::string& path,
              const char* key, bool allow_empty, std::string* out) {
  if (map[key] && y.ok()) *out = y.Text(map, path, key, allow_empty);
}

// A ROS namespace: names separated by single '/', none at either end.
bool IsNamespace(const std::string& ns) {
  return ns.empty() ||
         (ns.front() != '/' && ns.back() != '/' && ns.find("//") == std::string::npos &&
          ns.find_first_of(" \t") == std::string::npos);
}

void ReadDdsInputs(core::internal::YamlFields& y, const YAML::Node& n, DdsInputConfig* d) {
  const std::string at = "inputs.dds";
  d->enabled = true;
  if (n.IsNull()) return;  // `dds:` alone: every default
  if (!y.ExpectMap(n, at)) return;
  y.CheckKeys(
      n, at,
      {"odometry", "scan", "image", "initial_pose", "namespace", "stamp_check", "qos", "odom_frame",
       "base_frame", "lidar_frame", "camera_frame", "left_wheel_joint", "right_wheel_joint"});
  ReadChoice(y, n, at, "odometry", {"odom", "joint_states"}, &d->odometry);
  ReadBool(y, n, at, "scan", &d->scan);
  ReadBool(y, n, at, "image", &d->image);
  ReadBool(y, n, at, "initial_pose", &d->initial_pose);
  ReadText(y, n, at, "namespace", true, &d->ros_namespace);
  if (y.ok() && !IsNamespace(d->ros_namespace)) {
    y.Fail(n["namespace"], at + ".namespace", "a ROS namespace without leading or trailing '/'",
           d->ros_namespace);
  }
  ReadChoice(y, n, at, "stamp_check", {"wall", "newest", "none"}, &d->stamp_check);
  ReadChoice(y, n, at, "qos", {"sensor_data", "lossless"}, &d->qos);
  ReadText(y, n, at, "odom_frame", false, &d->odom_frame);
  ReadText(y, n, at, "base_frame", false, &d->base_frame);
  ReadText(y, n, at, "lidar_frame", false, &d->lidar_frame);
  ReadText(y, n, at, "camera_frame", true, &d->camera_frame);
  ReadText(y, n, at, "left_wheel_joint", false, &d->left_wheel_joint);
  ReadText(y, n, at, "right_wheel_joint", false, &d->right_wheel_joint);
  if (y.ok() && d->left_wheel_joint == d->right_wheel_joint) {
    y.Fail(n["right_wheel_joint"] ? n["right_wheel_joint"] : n, at + ".right_wheel_joint",
           "a joint name other than left_wheel_joint's", d->right_wheel_joint);
  }
}

void ReadDdsOutputs(core::internal::YamlFields& y, const YAML::Node& n, DdsOutputConfig* d) {
  const std::string at = "output.dds";
  if (!y.ExpectMap(n, at)) return;
  y.CheckKeys(n, at,
              {"enabled", "pose", "tf", "diagnostics", "namespace", "map_frame", "odom_frame",
               "base_frame", "transform_tolerance_s", "diagnostics_period_s"});
  d->enabled = true;
  ReadBool(y, n, at, "enabled", &d->enabled);
  ReadBool(y, n, at, "pose", &d->pose);
  ReadBool(y, n, at, "tf", &d->tf);
  ReadBool(y, n, at, "diagnostics", &d->diagnostics);
  ReadText(y, n, at, "namespace", true, &d->ros_namespace);
  if (y.ok() && !IsNamespace(d->ros_namespace)) {
    y.Fail(n["namespace"], at + ".namespace", "a ROS namespace without leading or trailing '/'",
           d->ros_namespace);
  }
  ReadText(y, n, at, "map_frame", false, &d->map_frame);
  ReadText(y, n, at, "odom_frame", false, &d->odom_frame);
  ReadText(y, n, at, "base_frame", false, &d->base_frame);
  if (n["transform_tolerance_s"] && y.ok()) {
    d->transform_tolerance_s = y.Number(n, at, "transform_tolerance_s");
    if (y.ok() && !(d->transform_tolerance_s >= 0.0 && d->transform_tolerance_s <= 1.0)) {
      y.Fail(n["transform_tolerance_s"], at + ".transform_tolerance_s", "0..1 s",
             std::to_string(d->transform_tolerance_s));
    }
  }
  if (n["diagnostics_period_s"] && y.ok()) {
    d->diagnostics_period_s = y.Number(n, at, "diagnostics_period_s");
    if (y.ok() && !(d->diagnostics_period_s >= 0.1 && d->diagnostics_period_s <= 60.0)) {
      y.Fail(n["diagnostics_period_s"], at + ".diagnostics_period_s", "0.1..60 s",
             std::to_string(d->diagnostics_period_s));
    }
  }
}

}  // namespace

perception::BevExtent ServiceConfig::Bev() const {
  perception::BevExtent bev;
  bev.x_m = bev_x_m;
  bev.y_m = bev_y_m;
  bev.cell_m = bev_cell_m;
  return bev;
}

core::Status ServiceConfig::Validate() const {
  if (core::Status s = Bev().Validate(); !s.ok()) return s.WithContext("localizer.bev");
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
    const bool known = f.sensor == Sensor::kCamera
                           ? (f.kind == "silent" || f.kind == "blackout" || f.kind == "corrupt")
                       : f.sensor == Sensor::kLidar ? f.kind == "silent"
                       : f.sensor == Sensor::kClock
                           ? f.kind == "jump"
                           : (f.kind == "nan" || f.kind == "frozen" || f.kind == "reorder" ||
                              f.kind == "duplicate");
    if (!known) {
      return core::Status::Error(
          at +
          ".kind: expected camera silent|blackout|corrupt, lidar "
          "silent, odometry nan|frozen|reorder|duplicate, clock jump, got '" +
          f.kind + "'");
    }
    if (f.sensor == Sensor::kClock) {
      if (!(std::isfinite(f.from_s) && f.from_s >= 0.0 && std::isfinite(f.by_s) && f.by_s != 0.0 &&
            std::abs(f.by_s) <= 1e7)) {
        return core::Status::Error(at + ": expected from_s >= 0 and a finite by_s != 0 [s]");
      }
    } else if (!(std::isfinite(f.from_s) && std::isfinite(f.to_s) && f.from_s >= 0.0 &&
                 f.to_s > f.from_s)) {
      return core::Status::Error(at + ": expected 0 <= from_s < to_s");
    }
  }
  if (!camera_uri.empty() && replay_speed == 0.0 && !dds_inputs.enabled) {
    return core::Status::Error(
        "inputs.camera.uri: a camera delivers frames at its own pace: set inputs.replay.speed "
        "> 0 (the replay's odometry and scans then follow the wall clock too)");
  }
  if (dds_inputs.enabled) {
    if (dds_inputs.odometry != "odom" && dds_inputs.odometry != "joint_states") {
      return core::Status::Error("inputs.dds.odometry: expected odom or joint_states, got '" +
                                 dds_inputs.odometry + "'");
    }
    if (!faults.empty()) {
      return core::Status::Error(
          "inputs.replay.faults: injected faults belong to the replay; with inputs.dds the "
          "replay's logs are not read");
    }
    if (dds_inputs.image && !camera_uri.empty()) {
      return core::Status::Error(
          "inputs.dds.image: the frames come from inputs.camera.uri already; set one of them");
    }
  }
  if (wait_for_initial_pose && !(dds_inputs.enabled && dds_inputs.initial_pose)) {
    return core::Status::Error(
        "start.wait_for_initial_pose: needs inputs.dds with initial_pose: true (the pose comes "
        "from rt/initialpose)");
  }
  if (wait_for_initial_pose && (initial_pose || relocalize)) {
    return core::Status::Error(
        "start.wait_for_initial_pose: conflicts with start.initial_pose / start.relocalize");
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
  if (self_calibration && preset != "fusion" && preset != "lines") {
    return core::Status::Error(
        "localizer.self_calibration: needs the camera's lines, the fusion or lines preset");
  }
  if (keep_atlas_current && preset != "fusion" && preset != "lines") {
    return core::Status::Error(
        "localizer.keep_atlas_current: needs an atlas to keep, the fusion or lines preset");
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
    y.CheckKeys(inputs, "inputs", {"replay", "camera", "dds"});
    if (const YAML::Node dds = inputs["dds"]) ReadDdsInputs(y, dds, &c.dds_inputs);
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
            y.Fail(faults[i]["sensor"], at + ".sensor", "camera, lidar, odometry or clock", sensor);
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
    y.CheckKeys(n, "localizer",
                {"preset", "atlas", "self_calibration", "mount_estimate", "bev",
                 "keep_atlas_current", "odometry_calibration"});
    if (const YAML::Node bev = n["bev"]; bev && y.ExpectMap(bev, "localizer.bev")) {
      y.CheckKeys(bev, "localizer.bev", {"x_m", "y_m", "cell_m"});
      for (const auto& [key, range] :
           {std::pair{"x_m", &c.bev_x_m}, std::pair{"y_m", &c.bev_y_m}}) {
        const std::string at = std::string("localizer.bev.") + key;
        const YAML::Node p = bev[key];
        if (!p || !y.ExpectSequence(p, at)) continue;
        if (p.size() != 2) {
          y.Fail(p, at, "two numbers [min, max] in metres", std::to_string(p.size()) + " values");
          continue;
        }
        *range = std::array<double, 2>{y.NumberAt(p[0], at + "[0]"), y.NumberAt(p[1], at + "[1]")};
      }
      if (bev["cell_m"]) c.bev_cell_m = y.Number(bev, "localizer.bev", "cell_m");
    }
    if (n["preset"]) c.preset = y.Text(n, "localizer", "preset");
    if (n["atlas"]) c.atlas = y.Text(n, "localizer", "atlas");
    if (n["odometry_calibration"])
      c.odometry_calibration = y.Text(n, "localizer", "odometry_calibration");
    if (n["mount_estimate"]) c.mount_estimate = y.Text(n, "localizer", "mount_estimate");
    ReadBool(y, n, "localizer", "self_calibration", &c.self_calibration);
    ReadBool(y, n, "localizer", "keep_atlas_current", &c.keep_atlas_current);
  }
  if (const YAML::Node n = y.Child(root, "", "start", false); n && y.ExpectMap(n, "start")) {
    y.CheckKeys(n, "start", {"initial_pose", "relocalize", "resume", "wait_for_initial_pose"});
    if (n["wait_for_initial_pose"])
      c.wait_for_initial_pose = y.BoolAt(n["wait_for_initial_pose"], "start.wait_for_initial_pose");
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
    y.CheckKeys(output, "output", {"dir", "dds"});
    c.output_dir = y.Text(output, "output", "dir");
    if (const YAML::Node dds = output["dds"]) ReadDdsOutputs(y, dds, &c.dds_outputs);
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
  for (std::string* p : {&c.replay_dataset, &c.atlas, &c.odometry_calibration, &c.output_dir}) {
    if (!p->empty() && std::filesystem::path(*p).is_relative()) *p = (base / *p).string();
  }
  if (core::Status s = c.Validate(); !s.ok()) return s.WithContext(path.string());
  return c;
}

}  // namespace groundline::service
