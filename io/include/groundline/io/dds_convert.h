// Conversions between groundline's types and the ROS 2 wire types.
//
// Stamps: groundline stamps are float64 seconds of one clock; ROS 2 stamps are
// (int32 sec, uint32 nanosec in [0, 1e9)), the same instant rounded to the
// nearest nanosecond.
// Planar poses: an SE(2) T_a_b (x, y, yaw) is the 3D pose (x, y, 0) with the
// rotation yaw about z, quaternion (0, 0, sin(yaw/2), cos(yaw/2)). Reading a
// 3D pose back takes yaw = atan2(2(wz + xy), 1 - 2(y^2 + z^2)) and ignores
// z, roll and pitch.
// Covariances: ROS 2 stores a row-major 6x6 matrix over (x, y, z, rotation
// about x, rotation about y, rotation about z). A groundline 3x3 covariance
// over (x, y, yaw) fills rows/columns {0, 1, 5}; the unobserved z, roll and
// pitch get kUnobservedVariance on the diagonal (as nav2 AMCL leaves them
// near zero but rviz needs a non-singular matrix, a large variance says
// "not estimated" unambiguously) and zero correlation.
// Note: groundline's pose covariance is in the right-perturbation tangent
// space of T (docs/conventions.md); ROS does not define the convention and
// most consumers read it as the covariance of (x, y) in the parent frame.
// For the small rotations of a localized pose the difference is the rotation
// of the (x, y) block by yaw, which ToPoseCovariance6 applies.
#ifndef GROUNDLINE_IO_DDS_CONVERT_H_
#define GROUNDLINE_IO_DDS_CONVERT_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/io/dds_types.h"

namespace groundline::io {

inline constexpr double kUnobservedVariance = 1e6;

// Nearest-nanosecond conversion; stamps outside the int32 seconds range are
// a contract violation (asserted).
RosTime ToRosTime(double stamp_s);
double FromRosTime(const RosTime& t);

// The 6x6 row-major covariance of an SE(2) pose whose 3x3 covariance is in
// its right-perturbation tangent space (see above): the (x, y) rows are
// rotated into the parent frame, Sigma_parent = A Sigma A^T with
// A = blockdiag(R(yaw), 1).
std::array<double, 36> ToPoseCovariance6(const core::SE2& T_parent_child,
                                         const core::Matrix3& covariance);
// The inverse: the (x, y, yaw) block of a 6x6 parent-frame covariance,
// rotated back into the tangent space of T_parent_child.
core::Matrix3 FromPoseCovariance6(const core::SE2& T_parent_child, const double covariance[36]);

struct PlanarPoseStamped {
  double stamp_s = 0.0;
  std::string frame_id;
  core::SE2 T_frame_base;
  core::Matrix3 covariance = core::Matrix3::Zero();  // tangent space of T_frame_base
};

DdsSample<RosPoseWithCovarianceStamped> ToPoseWithCovarianceStamped(const PlanarPoseStamped& pose);
// Call ValidatePoseWithCovarianceStamped first (NaNs pass through).
PlanarPoseStamped FromPoseWithCovarianceStamped(const RosPoseWithCovarianceStamped& msg);

// Planar odometry: T_odom_base and its covariance, and the body-frame velocity.
struct PlanarOdometry {
  double stamp_s = 0.0;
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  core::SE2 T_odom_base;
  core::Matrix3 covariance = core::Matrix3::Zero();
  double forward_velocity_mps = 0.0;  // along base_link x
  double yaw_rate_radps = 0.0;
  // (vx, vy, omega) in base_link; rows/columns {0, 1, 5} of the twist covariance.
  core::Matrix3 twist_covariance = core::Matrix3::Zero();
};

DdsSample<RosOdometry> ToOdometry(const PlanarOdometry& odometry);
// Call ValidateOdometry first.
PlanarOdometry FromOdometry(const RosOdometry& msg);

// One transform parent -> child (T_parent_child) in a TFMessage, e.g. map -> odom.
struct PlanarTransformStamped {
  double stamp_s = 0.0;
  std::string parent_frame;
  std::string child_frame;
  core::SE2 T_parent_child;
};
DdsSample<RosTfMessage> ToTfMessage(const std::vector<PlanarTransformStamped>& transforms);

// Wheel joint angles (absolute, rad) as ROS 2 drivers publish them.
struct WheelJointState {
  double stamp_s = 0.0;
  std::string frame_id;  // usually empty for joint states
  std::vector<std::string> names;
  std::vector<double> position_rad;
  std::vector<double> velocity_radps;  // empty or one per joint
};
DdsSample<RosJointState> ToJointState(const WheelJointState& state);

// diagnostic_msgs/DiagnosticStatus levels.
enum class DiagnosticLevel : std::uint8_t { kOk = 0, kWarn = 1, kError = 2, kStale = 3 };
struct DiagnosticEntry {
  DiagnosticLevel level = DiagnosticLevel::kOk;
  std::string name;  // "groundline: localizer"
  std::string message;
  std::string hardware_id;
  std::vector<std::pair<std::string, std::string>> values;
};
DdsSample<RosDiagnosticArray> ToDiagnosticArray(double stamp_s,
                                                const std::vector<DiagnosticEntry>& entries);

// Sets header.stamp and header.frame_id (which must be null or owned by msg).
void SetHeader(double stamp_s, const std::string& frame_id, RosHeader* header);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_DDS_CONVERT_H_
