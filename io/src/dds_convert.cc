#include "groundline/io/dds_convert.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>

namespace groundline::io {
namespace {

// Rows/columns of (x, y, yaw) in ROS's (x, y, z, rotX, rotY, rotZ).
constexpr int kRosIndex[3] = {0, 1, 5};

void SetPose(const core::SE2& T, geometry_msgs_msg_dds__Pose_* pose) {
  pose->position.x = T.translation().x();
  pose->position.y = T.translation().y();
  pose->position.z = 0.0;
  pose->orientation.x = 0.0;
  pose->orientation.y = 0.0;
  pose->orientation.z = std::sin(0.5 * T.yaw());
  pose->orientation.w = std::cos(0.5 * T.yaw());
}

core::SE2 GetPose(const geometry_msgs_msg_dds__Pose_& pose) {
  const auto& q = pose.orientation;
  const double yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
  return core::SE2(pose.position.x, pose.position.y, yaw);
}

void SetPlanarCovariance6(const core::Matrix3& c, double out[36]) {
  for (int i = 0; i < 36; ++i) out[i] = 0.0;
  for (int i = 2; i < 5; ++i) out[i * 6 + i] = kUnobservedVariance;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) out[kRosIndex[r] * 6 + kRosIndex[k]] = c(r, k);
  }
}

core::Matrix3 GetPlanarCovariance6(const double in[36]) {
  core::Matrix3 c;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) c(r, k) = in[kRosIndex[r] * 6 + kRosIndex[k]];
  }
  return c;
}

core::Matrix3 TangentToParent(const core::SE2& T) {
  core::Matrix3 A = core::Matrix3::Identity();
  A.topLeftCorner<2, 2>() = T.Rotation();
  return A;
}

}  // namespace

char* DdsStringDup(std::string_view s) {
  char* out = static_cast<char*>(dds_alloc(s.size() + 1));
  if (!s.empty()) std::memcpy(out, s.data(), s.size());
  out[s.size()] = '\0';
  return out;
}

RosTime ToRosTime(double stamp_s) {
  assert(std::isfinite(stamp_s));
  double sec = std::floor(stamp_s);
  double nsec = std::round((stamp_s - sec) * 1e9);
  if (nsec >= 1e9) {
    sec += 1.0;
    nsec -= 1e9;
  }
  assert(sec >= std::numeric_limits<std::int32_t>::min() &&
         sec <= std::numeric_limits<std::int32_t>::max());
  RosTime t;
  t.sec = static_cast<std::int32_t>(sec);
  t.nanosec = static_cast<std::uint32_t>(nsec);
  return t;
}

double FromRosTime(const RosTime& t) { return static_cast<double>(t.sec) + 1e-9 * t.nanosec; }

void SetHeader(double stamp_s, const std::string& frame_id, RosHeader* header) {
  header->stamp = ToRosTime(stamp_s);
  dds_free(header->frame_id);
  header->frame_id = DdsStringDup(frame_id);
}

std::array<double, 36> ToPoseCovariance6(const core::SE2& T_parent_child,
                                         const core::Matrix3& covariance) {
  const core::Matrix3 A = TangentToParent(T_parent_child);
  std::array<double, 36> out;
  SetPlanarCovariance6(A * covariance * A.transpose(), out.data());
  return out;
}

core::Matrix3 FromPoseCovariance6(const core::SE2& T_parent_child, const double covariance[36]) {
  const core::Matrix3 A = TangentToParent(T_parent_child);
  return A.transpose() * GetPlanarCovariance6(covariance) * A;
}

DdsSample<RosPoseWithCovarianceStamped> ToPoseWithCovarianceStamped(const PlanarPoseStamped& pose) {
  DdsSample<RosPoseWithCovarianceStamped> out;
  SetHeader(pose.stamp_s, pose.frame_id, &out.msg().header);
  SetPose(pose.T_frame_base, &out.msg().pose.pose);
  const std::array<double, 36> c = ToPoseCovariance6(pose.T_frame_base, pose.covariance);
  std::copy(c.begin(), c.end(), out.msg().pose.covariance);
  return out;
}

PlanarPoseStamped FromPoseWithCovarianceStamped(const RosPoseWithCovarianceStamped& msg) {
  PlanarPoseStamped out;
  out.stamp_s = FromRosTime(msg.header.stamp);
  out.frame_id = msg.header.frame_id != nullptr ? msg.header.frame_id : "";
  out.T_frame_base = GetPose(msg.pose.pose);
  out.covariance = FromPoseCovariance6(out.T_frame_base, msg.pose.covariance);
  return out;
}

DdsSample<RosOdometry> ToOdometry(const PlanarOdometry& odometry) {
  DdsSample<RosOdometry> out;
  RosOdometry& m = out.msg();
  SetHeader(odometry.stamp_s, odometry.odom_frame, &m.header);
  m.child_frame_id = DdsStringDup(odometry.base_frame);
  SetPose(odometry.T_odom_base, &m.pose.pose);
  const std::array<double, 36> c = ToPoseCovariance6(odometry.T_odom_base, odometry.covariance);
  std::copy(c.begin(), c.end(), m.pose.covariance);
  m.twist.twist.linear.x = odometry.forward_velocity_mps;
  m.twist.twist.angular.z = odometry.yaw_rate_radps;
  SetPlanarCovariance6(odometry.twist_covariance, m.twist.covariance);
  return out;
}

PlanarOdometry FromOdometry(const RosOdometry& msg) {
  PlanarOdometry out;
  out.stamp_s = FromRosTime(msg.header.stamp);
  out.odom_frame = msg.header.frame_id != nullptr ? msg.header.frame_id : "";
  out.base_frame = msg.child_frame_id != nullptr ? msg.child_frame_id : "";
  out.T_odom_base = GetPose(msg.pose.pose);
  out.covariance = FromPoseCovariance6(out.T_odom_base, msg.pose.covariance);
  out.forward_velocity_mps = msg.twist.twist.linear.x;
  out.yaw_rate_radps = msg.twist.twist.angular.z;
  out.twist_covariance = GetPlanarCovariance6(msg.twist.covariance);
  return out;
}

DdsSample<RosTfMessage> ToTfMessage(const std::vector<PlanarTransformStamped>& transforms) {
  DdsSample<RosTfMessage> out;
  DdsAllocSequence(&out.msg().transforms, static_cast<std::uint32_t>(transforms.size()));
  for (std::size_t i = 0; i < transforms.size(); ++i) {
    const PlanarTransformStamped& in = transforms[i];
    RosTransformStamped& t = out.msg().transforms._buffer[i];
    SetHeader(in.stamp_s, in.parent_frame, &t.header);
    t.child_frame_id = DdsStringDup(in.child_frame);
    geometry_msgs_msg_dds__Pose_ pose;
    SetPose(in.T_parent_child, &pose);
    t.transform.translation.x = pose.position.x;
    t.transform.translation.y = pose.position.y;
    t.transform.translation.z = 0.0;
    t.transform.rotation = pose.orientation;
  }
  return out;
}

DdsSample<RosJointState> ToJointState(const WheelJointState& state) {
  assert(state.position_rad.size() == state.names.size());
  assert(state.velocity_radps.empty() || state.velocity_radps.size() == state.names.size());
  DdsSample<RosJointState> out;
  RosJointState& m = out.msg();
  SetHeader(state.stamp_s, state.frame_id, &m.header);
  const auto n = static_cast<std::uint32_t>(state.names.size());
  DdsAllocSequence(&m.name, n);
  DdsAllocSequence(&m.position, n);
  DdsAllocSequence(&m.velocity, static_cast<std::uint32_t>(state.velocity_radps.size()));
  DdsAllocSequence(&m.effort, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    m.name._buffer[i] = DdsStringDup(state.names[i]);
    m.position._buffer[i] = state.position_rad[i];
  }
  for (std::size_t i = 0; i < state.velocity_radps.size(); ++i) {
    m.velocity._buffer[i] = state.velocity_radps[i];
  }
  return out;
}

DdsSample<RosDiagnosticArray> ToDiagnosticArray(double stamp_s,
                                                const std::vector<DiagnosticEntry>& entries) {
  DdsSample<RosDiagnosticArray> out;
  SetHeader(stamp_s, "", &out.msg().header);
  DdsAllocSequence(&out.msg().status, static_cast<std::uint32_t>(entries.size()));
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const DiagnosticEntry& e = entries[i];
    RosDiagnosticStatus& s = out.msg().status._buffer[i];
    s.level = static_cast<std::uint8_t>(e.level);
    s.name = DdsStringDup(e.name);
    s.message = DdsStringDup(e.message);
    s.hardware_id = DdsStringDup(e.hardware_id);
    DdsAllocSequence(&s.values, static_cast<std::uint32_t>(e.values.size()));
    for (std::size_t k = 0; k < e.values.size(); ++k) {
      s.values._buffer[k].key = DdsStringDup(e.values[k].first);
      s.values._buffer[k].value = DdsStringDup(e.values[k].second);
    }
  }
  return out;
}

}  // namespace groundline::io
