#include "carmen_parse.h"

#include <cassert>
#include <span>
#include <string>
#include <utility>

#include "text_fields.h"

namespace groundline::io::internal {
namespace {

// Walks the fields of one message (fields[0] is the message name) and turns
// every failure into a message naming the field and its 1-based position.
class FieldCursor {
 public:
  explicit FieldCursor(std::span<const std::string_view> fields) : fields_(fields) {}

  std::size_t remaining() const { return fields_.size() - next_; }

  core::Status Double(std::string_view name, double* value) {
    if (next_ >= fields_.size()) return Missing(name);
    if (!ParseFiniteDouble(fields_[next_], value)) return Bad(name, "a finite number");
    ++next_;
    return core::Status::Ok();
  }

  core::Status Int(std::string_view name, int64_t* value) {
    if (next_ >= fields_.size()) return Missing(name);
    if (!ParseInt64(fields_[next_], value)) return Bad(name, "an integer");
    ++next_;
    return core::Status::Ok();
  }

  core::Status Text(std::string_view name, std::string_view* value) {
    if (next_ >= fields_.size()) return Missing(name);
    *value = fields_[next_++];
    return core::Status::Ok();
  }

  // A count n followed by n values and then at least `fields_after` fields.
  core::Status Count(std::string_view name, int64_t max_count, std::size_t fields_after,
                     std::size_t* count) {
    const std::size_t position = next_;
    int64_t n = 0;
    if (core::Status status = Int(name, &n); !status.ok()) return status;
    if (n < 0 || n > max_count) {
      return FieldError(
          name, position,
          "expected a count in [0, " + std::to_string(max_count) + "], got " + std::to_string(n));
    }
    const std::size_t needed = static_cast<std::size_t>(n) + fields_after;
    if (needed > remaining()) {
      return FieldError(name, position,
                        "count " + std::to_string(n) + " overruns the line: it needs " +
                            std::to_string(needed) + " more fields (" + std::to_string(n) +
                            " values + " + std::to_string(fields_after) +
                            " after them), the line has " + std::to_string(remaining()));
    }
    *count = static_cast<std::size_t>(n);
    return core::Status::Ok();
  }

  // n values named "name[i]".
  core::Status Doubles(std::string_view name, std::size_t n, std::vector<double>* values) {
    values->resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (next_ >= fields_.size() || !ParseFiniteDouble(fields_[next_], &(*values)[i])) {
        return Double(std::string(name) + "[" + std::to_string(i) + "]", &(*values)[i]);
      }
      ++next_;
    }
    return core::Status::Ok();
  }

  // Three fields prefix_x, prefix_y, prefix_theta.
  core::Status Pose(std::string_view prefix, core::SE2* pose) {
    const std::string p(prefix);
    double x = 0.0, y = 0.0, theta = 0.0;
    if (core::Status s = Double(p + "x", &x); !s.ok()) return s;
    if (core::Status s = Double(p + "y", &y); !s.ok()) return s;
    if (core::Status s = Double(p + "theta", &theta); !s.ok()) return s;
    *pose = core::SE2(x, y, theta);
    return core::Status::Ok();
  }

  // ipc_timestamp ipc_hostname logger_timestamp, then the end of the line.
  core::Status Tail(double* stamp_s, double* logger_stamp_s) {
    std::string_view host;
    if (core::Status s = Double("ipc_timestamp", stamp_s); !s.ok()) return s;
    if (core::Status s = Text("ipc_hostname", &host); !s.ok()) return s;
    if (core::Status s = Double("logger_timestamp", logger_stamp_s); !s.ok()) return s;
    if (remaining() > 0) {
      return core::Status::Error(
          std::string(fields_[0]) + ": " + std::to_string(remaining()) +
          " extra fields after 'logger_timestamp' (field " + std::to_string(next_) +
          "; the line has " + std::to_string(fields_.size()) +
          "): a count does not match the number of values, or the line is garbled");
    }
    return core::Status::Ok();
  }

 private:
  core::Status FieldError(std::string_view name, std::size_t position,
                          const std::string& what) const {
    return core::Status::Error(std::string(fields_[0]) + " field '" + std::string(name) +
                               "' (field " + std::to_string(position + 1) + "): " + what);
  }
  core::Status Missing(std::string_view name) const {
    return FieldError(name, next_,
                      "missing: the line ends after " + std::to_string(fields_.size()) +
                          " fields (too few fields, or a truncated line)");
  }
  core::Status Bad(std::string_view name, std::string_view expected) const {
    return FieldError(name, next_,
                      "expected " + std::string(expected) + ", got " + QuoteField(fields_[next_]));
  }

  std::span<const std::string_view> fields_;
  std::size_t next_ = 1;  // fields_[0] is the message name
};

bool IsMessageName(std::string_view name) {
  auto alpha = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); };
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  if (name.empty() || !alpha(name.front())) return false;
  for (char c : name) {
    if (!alpha(c) && !digit(c) && c != '_' && c != '-') return false;
  }
  return true;
}

// "RAWLASER3" with prefix "RAWLASER" -> 3; nullopt if not prefix + digits.
std::optional<int> LaserNumber(std::string_view name, std::string_view prefix) {
  if (name.size() <= prefix.size() || name.substr(0, prefix.size()) != prefix) return std::nullopt;
  int64_t number = 0;
  const std::string_view digits = name.substr(prefix.size());
  if (digits.size() > 3 || digits.front() == '+' || digits.front() == '-' ||
      !ParseInt64(digits, &number)) {
    return std::nullopt;
  }
  return static_cast<int>(number);
}

// PARAM name value [ipc_timestamp] hostname logger_timestamp. The value may
// contain spaces; the optional ipc_timestamp is recognised as a number.
core::Status ParseParam(std::span<const std::string_view> f, CarmenParam* param) {
  const std::size_t n = f.size();
  if (n < 5) {
    return core::Status::Error(
        "PARAM: expected 'PARAM name value [ipc_timestamp] hostname "
        "logger_timestamp', got " +
        std::to_string(n) + " fields");
  }
  double stamp = 0.0;
  if (!ParseFiniteDouble(f[n - 1], &stamp)) {
    return core::Status::Error("PARAM field 'logger_timestamp' (field " + std::to_string(n) +
                               "): expected a finite number, got " + QuoteField(f[n - 1]));
  }
  std::size_t value_end = n - 2;  // index of hostname
  if (n >= 6 && ParseFiniteDouble(f[n - 3], &stamp)) value_end = n - 3;
  param->name = std::string(f[1]);
  param->value.clear();
  for (std::size_t i = 2; i < value_end; ++i) {
    if (i > 2) param->value += ' ';
    param->value.append(f[i]);
  }
  return core::Status::Ok();
}

core::Status ParseOdometry(FieldCursor* c, CarmenOdometry* odom) {
  if (core::Status s = c->Pose("", &odom->pose); !s.ok()) return s;
  if (core::Status s = c->Double("tv", &odom->tv_mps); !s.ok()) return s;
  if (core::Status s = c->Double("rv", &odom->rv_radps); !s.ok()) return s;
  if (core::Status s = c->Double("accel", &odom->accel_mps2); !s.ok()) return s;
  return c->Tail(&odom->stamp_s, &odom->logger_stamp_s);
}

core::Status ParseTruePose(FieldCursor* c, CarmenTruePose* pose) {
  if (core::Status s = c->Pose("true_", &pose->true_pose); !s.ok()) return s;
  if (core::Status s = c->Pose("odom_", &pose->odom_pose); !s.ok()) return s;
  return c->Tail(&pose->stamp_s, &pose->logger_stamp_s);
}

// FLASER / RLASER num_readings [ranges] x y theta odom_x odom_y odom_theta tail.
core::Status ParseOldLaser(FieldCursor* c, const CarmenReadOptions& options,
                           CarmenLaserScan* scan) {
  std::size_t n = 0;
  if (core::Status s = c->Count("num_readings", options.max_readings, 6 + 3, &n); !s.ok()) {
    return s;
  }
  if (core::Status s = c->Doubles("range", n, &scan->ranges_m); !s.ok()) return s;
  core::SE2 laser_pose, robot_pose;
  if (core::Status s = c->Pose("", &laser_pose); !s.ok()) return s;
  if (core::Status s = c->Pose("odom_", &robot_pose); !s.ok()) return s;
  scan->laser_pose = laser_pose;
  scan->robot_pose = robot_pose;
  scan->angle_min_rad = options.old_format_angle_min_rad;
  scan->angle_increment_rad = options.old_format_angle_increment_rad > 0.0
                                  ? options.old_format_angle_increment_rad
                                  : GuessOldFormatAngleIncrementRad(n);
  scan->max_range_m = options.old_format_max_range_m;
  return c->Tail(&scan->stamp_s, &scan->logger_stamp_s);
}

// The part shared by RAWLASERk and ROBOTLASERk, up to the remissions.
// `fields_after` counts the fields after the remissions (poses etc. + tail).
core::Status ParseNewLaserHead(FieldCursor* c, const CarmenReadOptions& options,
                               std::size_t fields_after, CarmenLaserScan* scan) {
  int64_t laser_type = 0, remission_mode = 0;
  double fov = 0.0, accuracy = 0.0;
  if (core::Status s = c->Int("laser_type", &laser_type); !s.ok()) return s;
  if (core::Status s = c->Double("start_angle", &scan->angle_min_rad); !s.ok()) return s;
  if (core::Status s = c->Double("field_of_view", &fov); !s.ok()) return s;
  if (core::Status s = c->Double("angular_resolution", &scan->angle_increment_rad); !s.ok()) {
    return s;
  }
  if (core::Status s = c->Double("maximum_range", &scan->max_range_m); !s.ok()) return s;
  if (core::Status s = c->Double("accuracy", &accuracy); !s.ok()) return s;
  if (core::Status s = c->Int("remission_mode", &remission_mode); !s.ok()) return s;
  scan->laser_type = static_cast<int>(laser_type);
  std::size_t n = 0, m = 0;
  // After the ranges: num_remissions (1) + at least 0 remissions + the rest.
  if (core::Status s = c->Count("num_readings", options.max_readings, 1 + fields_after, &n);
      !s.ok()) {
    return s;
  }
  if (core::Status s = c->Doubles("range", n, &scan->ranges_m); !s.ok()) return s;
  if (core::Status s = c->Count("num_remissions", options.max_readings, fields_after, &m);
      !s.ok()) {
    return s;
  }
  return c->Doubles("remission", m, &scan->remissions);
}

core::Status ParseRawLaser(FieldCursor* c, const CarmenReadOptions& options,
                           CarmenLaserScan* scan) {
  if (core::Status s = ParseNewLaserHead(c, options, 3, scan); !s.ok()) return s;
  return c->Tail(&scan->stamp_s, &scan->logger_stamp_s);
}

core::Status ParseRobotLaser(FieldCursor* c, const CarmenReadOptions& options,
                             CarmenLaserScan* scan) {
  if (core::Status s = ParseNewLaserHead(c, options, 6 + 5 + 3, scan); !s.ok()) return s;
  core::SE2 laser_pose, robot_pose;
  double forward_safety = 0.0, side_safety = 0.0, turn_axis = 0.0;
  if (core::Status s = c->Pose("laser_pose_", &laser_pose); !s.ok()) return s;
  if (core::Status s = c->Pose("robot_pose_", &robot_pose); !s.ok()) return s;
  if (core::Status s = c->Double("tv", &scan->tv_mps); !s.ok()) return s;
  if (core::Status s = c->Double("rv", &scan->rv_radps); !s.ok()) return s;
  if (core::Status s = c->Double("forward_safety_dist", &forward_safety); !s.ok()) return s;
  if (core::Status s = c->Double("side_safety_dist", &side_safety); !s.ok()) return s;
  if (core::Status s = c->Double("turn_axis", &turn_axis); !s.ok()) return s;
  scan->laser_pose = laser_pose;
  scan->robot_pose = robot_pose;
  return c->Tail(&scan->stamp_s, &scan->logger_stamp_s);
}

core::Status ParseLaser(std::string_view name, FieldCursor* c, const CarmenReadOptions& options,
                        int64_t line_number, ParsedCarmenLine* out) {
  CarmenLaserScan scan;
  scan.line = line_number;
  core::Status status = core::Status::Ok();
  if (name == "FLASER" || name == "RLASER") {
    scan.message = name == "FLASER" ? CarmenLaserMessage::kFlaser : CarmenLaserMessage::kRlaser;
    scan.laser_id = name == "FLASER" ? 1 : 2;
    status = ParseOldLaser(c, options, &scan);
  } else if (std::optional<int> id = LaserNumber(name, "RAWLASER")) {
    scan.message = CarmenLaserMessage::kRawLaser;
    scan.laser_id = *id;
    status = ParseRawLaser(c, options, &scan);
  } else if (std::optional<int> robot_id = LaserNumber(name, "ROBOTLASER")) {
    scan.message = CarmenLaserMessage::kRobotLaser;
    scan.laser_id = *robot_id;
    status = ParseRobotLaser(c, options, &scan);
  } else {
    out->type = CarmenLineType::kUnknown;
    return core::Status::Ok();
  }
  if (!status.ok()) return status;
  out->type = CarmenLineType::kMessage;
  out->message = std::move(scan);
  return core::Status::Ok();
}

}  // namespace

core::Status ParseCarmenLine(std::string_view line, int64_t line_number,
                             const CarmenReadOptions& options,
                             std::vector<std::string_view>* fields, ParsedCarmenLine* out) {
  assert(fields != nullptr && out != nullptr);
  out->type = CarmenLineType::kBlank;
  out->name = {};
  out->message.reset();
  SplitFields(line, fields);
  if (fields->empty()) return core::Status::Ok();
  const std::string_view name = fields->front();
  out->name = name;
  if (name.front() == '#') {
    out->type = CarmenLineType::kComment;
    return core::Status::Ok();
  }
  if (!IsMessageName(name)) {
    return core::Status::Error("expected a message name (letters, digits, '_', '-'), got " +
                               QuoteField(name));
  }
  FieldCursor cursor(*fields);
  if (name == "PARAM") {
    CarmenParam param;
    param.line = line_number;
    if (core::Status s = ParseParam(*fields, &param); !s.ok()) return s;
    out->type = CarmenLineType::kMessage;
    out->message = std::move(param);
    return core::Status::Ok();
  }
  if (name == "SYNC") {
    std::string_view tag;
    double stamp = 0.0, logger_stamp = 0.0;
    if (core::Status s = cursor.Text("tagname", &tag); !s.ok()) return s;
    if (core::Status s = cursor.Tail(&stamp, &logger_stamp); !s.ok()) return s;
    out->type = CarmenLineType::kCountedOnly;
    return core::Status::Ok();
  }
  if (name == "ODOM") {
    CarmenOdometry odom;
    odom.line = line_number;
    if (core::Status s = ParseOdometry(&cursor, &odom); !s.ok()) return s;
    out->type = CarmenLineType::kMessage;
    out->message = odom;
    return core::Status::Ok();
  }
  if (name == "TRUEPOS") {
    CarmenTruePose pose;
    pose.line = line_number;
    if (core::Status s = ParseTruePose(&cursor, &pose); !s.ok()) return s;
    out->type = CarmenLineType::kMessage;
    out->message = pose;
    return core::Status::Ok();
  }
  return ParseLaser(name, &cursor, options, line_number, out);
}

}  // namespace groundline::io::internal
