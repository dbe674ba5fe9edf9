#include "groundline/io/dds_validate.h"

#include <cmath>
#include <cstdio>

#include "groundline/io/dds_convert.h"

namespace groundline::io {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

core::Status FieldError(std::string_view type, const std::string& field, const std::string& what) {
  return core::Status::Error(std::string(type) + ": field '" + field + "': " + what);
}

core::Status Finite(std::string_view type, const std::string& field, double v) {
  if (std::isfinite(v)) return core::Status::Ok();
  return FieldError(type, field, "expected a finite number, got " + Num(v));
}

core::Status FiniteArray(std::string_view type, const std::string& field, const double* v, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) {
      return FieldError(type, field + "[" + std::to_string(i) + "]",
                        "expected a finite number, got " + Num(v[i]));
    }
  }
  return core::Status::Ok();
}

core::Status CheckPose(std::string_view type, const std::string& field,
                       const geometry_msgs_msg_dds__PoseWithCovariance_& p) {
  const auto& pos = p.pose.position;
  const auto& q = p.pose.orientation;
  const double values[7] = {pos.x, pos.y, pos.z, q.x, q.y, q.z, q.w};
  const char* names[7] = {"position.x",    "position.y",    "position.z",   "orientation.x",
                          "orientation.y", "orientation.z", "orientation.w"};
  for (int i = 0; i < 7; ++i) {
    if (core::Status s = Finite(type, field + ".pose." + names[i], values[i]); !s.ok()) return s;
  }
  const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (std::abs(norm - 1.0) > 1e-3) {
    return FieldError(type, field + ".pose.orientation",
                      "expected a unit quaternion, got norm " + Num(norm));
  }
  return FiniteArray(type, field + ".covariance", p.covariance, 36);
}

}  // namespace

core::Status DdsStampWindow::Validate() const {
  if (!(std::isfinite(max_stamp_age_s) && max_stamp_age_s >= 0.0)) {
    return core::Status::Error("DdsStampWindow.max_stamp_age_s: expected finite >= 0, got " +
                               Num(max_stamp_age_s));
  }
  if (!(std::isfinite(max_stamp_lead_s) && max_stamp_lead_s >= 0.0)) {
    return core::Status::Error("DdsStampWindow.max_stamp_lead_s: expected finite >= 0, got " +
                               Num(max_stamp_lead_s));
  }
  return core::Status::Ok();
}

core::Status ValidateHeader(std::string_view type, const RosHeader& header, const DdsCheck& check) {
  if (header.stamp.nanosec >= 1000000000u) {
    return FieldError(type, "header.stamp.nanosec",
                      "expected < 1e9, got " + std::to_string(header.stamp.nanosec));
  }
  const std::string frame = header.frame_id != nullptr ? header.frame_id : "";
  if (!check.frame_id.empty() && frame != check.frame_id) {
    return FieldError(type, "header.frame_id",
                      "expected '" + check.frame_id + "', got '" + frame + "'");
  }
  if (check.reference_s) {
    const double stamp_s = FromRosTime(header.stamp);
    const double dt = stamp_s - *check.reference_s;
    if (dt < -check.window.max_stamp_age_s || dt > check.window.max_stamp_lead_s) {
      return FieldError(type, "header.stamp",
                        Num(stamp_s) + " s is " + Num(dt) + " s from the reference " +
                            Num(*check.reference_s) + " s; accepted: [-" +
                            Num(check.window.max_stamp_age_s) + ", +" +
                            Num(check.window.max_stamp_lead_s) + "] s (check the sender's clock)");
    }
  }
  return core::Status::Ok();
}

core::Status ValidateLaserScan(const RosLaserScan& m, const DdsCheck& check) {
  constexpr std::string_view kType = DdsTraits<RosLaserScan>::kRosName;
  if (core::Status s = ValidateHeader(kType, m.header, check); !s.ok()) return s;
  const std::pair<const char*, float> fields[] = {{"angle_min", m.angle_min},
                                                  {"angle_max", m.angle_max},
                                                  {"angle_increment", m.angle_increment},
                                                  {"time_increment", m.time_increment},
                                                  {"scan_time", m.scan_time},
                                                  {"range_min", m.range_min},
                                                  {"range_max", m.range_max}};
  for (const auto& [name, value] : fields) {
    if (core::Status s = Finite(kType, name, value); !s.ok()) return s;
  }
  if (m.angle_increment == 0.0f) return FieldError(kType, "angle_increment", "expected != 0");
  if (!(m.range_min > 0.0f && m.range_min < m.range_max)) {
    return FieldError(
        kType, "range_min",
        "expected 0 < range_min < range_max, got " + Num(m.range_min) + " and " + Num(m.range_max));
  }
  const double expected =
      (static_cast<double>(m.angle_max) - m.angle_min) / static_cast<double>(m.angle_increment) +
      1.0;
  if (std::abs(expected - m.ranges._length) > 0.1) {
    return FieldError(
        kType, "ranges",
        std::to_string(m.ranges._length) +
            " values, but (angle_max - angle_min) / angle_increment + 1 = " + Num(expected));
  }
  if (m.intensities._length != 0 && m.intensities._length != m.ranges._length) {
    return FieldError(kType, "intensities",
                      std::to_string(m.intensities._length) + " values, expected 0 or " +
                          std::to_string(m.ranges._length));
  }
  return core::Status::Ok();
}

core::Status ValidateOdometry(const RosOdometry& m, const DdsCheck& check,
                              const std::string& expected_child) {
  constexpr std::string_view kType = DdsTraits<RosOdometry>::kRosName;
  if (core::Status s = ValidateHeader(kType, m.header, check); !s.ok()) return s;
  const std::string child = m.child_frame_id != nullptr ? m.child_frame_id : "";
  if (!expected_child.empty() && child != expected_child) {
    return FieldError(kType, "child_frame_id",
                      "expected '" + expected_child + "', got '" + child + "'");
  }
  if (core::Status s = CheckPose(kType, "pose", m.pose); !s.ok()) return s;
  const auto& t = m.twist.twist;
  const double twist[6] = {t.linear.x,  t.linear.y,  t.linear.z,
                           t.angular.x, t.angular.y, t.angular.z};
  if (core::Status s = FiniteArray(kType, "twist.twist(linear, angular)", twist, 6); !s.ok()) {
    return s;
  }
  return FiniteArray(kType, "twist.covariance", m.twist.covariance, 36);
}

core::Status ValidatePoseWithCovarianceStamped(const RosPoseWithCovarianceStamped& m,
                                               const DdsCheck& check) {
  constexpr std::string_view kType = DdsTraits<RosPoseWithCovarianceStamped>::kRosName;
  if (core::Status s = ValidateHeader(kType, m.header, check); !s.ok()) return s;
  return CheckPose(kType, "pose", m.pose);
}

core::Status ValidateJointState(const RosJointState& m, const DdsCheck& check,
                                const std::vector<std::string>& required_joints) {
  constexpr std::string_view kType = DdsTraits<RosJointState>::kRosName;
  if (core::Status s = ValidateHeader(kType, m.header, check); !s.ok()) return s;
  const std::uint32_t n = m.name._length;
  if (m.position._length != n) {
    return FieldError(
        kType, "position",
        std::to_string(m.position._length) + " values for " + std::to_string(n) + " names");
  }
  if (m.velocity._length != 0 && m.velocity._length != n) {
    return FieldError(
        kType, "velocity",
        std::to_string(m.velocity._length) + " values, expected 0 or " + std::to_string(n));
  }
  if (m.effort._length != 0 && m.effort._length != n) {
    return FieldError(
        kType, "effort",
        std::to_string(m.effort._length) + " values, expected 0 or " + std::to_string(n));
  }
  for (const std::string& joint : required_joints) {
    int found = -1;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (m.name._buffer[i] != nullptr && joint == m.name._buffer[i]) {
        if (found >= 0) return FieldError(kType, "name", "joint '" + joint + "' listed twice");
        found = static_cast<int>(i);
      }
    }
    if (found < 0) return FieldError(kType, "name", "joint '" + joint + "' missing");
    if (core::Status s = Finite(kType, "position[" + std::to_string(found) + "] (" + joint + ")",
                                m.position._buffer[found]);
        !s.ok()) {
      return s;
    }
  }
  return core::Status::Ok();
}

core::Status ValidateImage(const RosImage& m, const DdsCheck& check) {
  constexpr std::string_view kType = DdsTraits<RosImage>::kRosName;
  if (core::Status s = ValidateHeader(kType, m.header, check); !s.ok()) return s;
  const std::string encoding = m.encoding != nullptr ? m.encoding : "";
  if (encoding != "mono8") {
    return FieldError(kType, "encoding", "expected 'mono8', got '" + encoding + "'");
  }
  if (m.width == 0 || m.height == 0) {
    return FieldError(kType, "width",
                      "expected a non-empty image, got " + std::to_string(m.width) + " x " +
                          std::to_string(m.height));
  }
  if (m.step < m.width) {
    return FieldError(
        kType, "step",
        "expected >= width " + std::to_string(m.width) + ", got " + std::to_string(m.step));
  }
  if (static_cast<std::uint64_t>(m.step) * m.height != m.data._length) {
    return FieldError(kType, "data",
                      std::to_string(m.data._length) + " bytes, expected step * height = " +
                          std::to_string(static_cast<std::uint64_t>(m.step) * m.height));
  }
  return core::Status::Ok();
}

}  // namespace groundline::io
