// Checks of incoming ROS 2 messages before they reach an estimator. Each
// returns Ok or an error naming the message type and the field, e.g.
//   "sensor_msgs/LaserScan: field 'ranges': 361 values, but (angle_max -
//    angle_min) / angle_increment + 1 = 360.0"
// The consumer drops a message that fails and counts it (DdsInputs does).
//
// Common to all: every float field the conversion reads is finite; the
// header's frame_id equals the expected one (when one is expected); the stamp
// lies within [reference - max_stamp_age_s, reference + max_stamp_lead_s] of
// a reference stamp (when one is given), so that a driver with a wrong clock
// or a stale replay is caught instead of corrupting the time order.
#ifndef GROUNDLINE_IO_DDS_VALIDATE_H_
#define GROUNDLINE_IO_DDS_VALIDATE_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/io/dds_types.h"

namespace groundline::io {

struct DdsStampWindow {
  double max_stamp_age_s = 1.0;   // how far behind the reference a stamp may be
  double max_stamp_lead_s = 0.2;  // how far ahead (clock offsets between hosts)

  // Ok if both are finite and >= 0.
  core::Status Validate() const;
};

struct DdsCheck {
  std::string frame_id;               // empty: any frame
  std::optional<double> reference_s;  // unset: no stamp check
  DdsStampWindow window;
};

// Header alone (for types without other checks).
core::Status ValidateHeader(std::string_view type_name, const RosHeader& header,
                            const DdsCheck& check);

// Beyond the header: finite angles and limits, angle_increment != 0,
// 0 < range_min < range_max, ranges count within 0.1 beam of
// (angle_max - angle_min) / angle_increment + 1, intensities empty or one per
// range. Range values may be NaN/Inf (REP-117 no-returns).
core::Status ValidateLaserScan(const RosLaserScan& msg, const DdsCheck& check);

// Header, child_frame_id (== expected_child when non-empty), finite pose,
// twist and covariances, a unit quaternion within 1e-3.
core::Status ValidateOdometry(const RosOdometry& msg, const DdsCheck& check,
                              const std::string& expected_child = "");

core::Status ValidatePoseWithCovarianceStamped(const RosPoseWithCovarianceStamped& msg,
                                               const DdsCheck& check);

// Header; every name in `required_joints` present once; position finite for
// those joints; velocity/effort empty or one per name.
core::Status ValidateJointState(const RosJointState& msg, const DdsCheck& check,
                                const std::vector<std::string>& required_joints);

// Header; encoding mono8; step >= width; data = step * height bytes.
core::Status ValidateImage(const RosImage& msg, const DdsCheck& check);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_DDS_VALIDATE_H_
