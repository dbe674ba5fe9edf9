// The outputs of the localization service over ROS 2 topics:
//   pose        geometry_msgs/PoseWithCovarianceStamped, T_map_base, QoS kPoseOutput
//               (reliable, transient local, depth 1: a late subscriber gets the last pose)
//   tf          tf2_msgs/TFMessage map -> odom, QoS kTf
//   diagnostics diagnostic_msgs/DiagnosticArray, QoS kDefault
// The participant must outlive the object. Publishing is thread-safe.
#ifndef GROUNDLINE_IO_DDS_OUTPUTS_H_
#define GROUNDLINE_IO_DDS_OUTPUTS_H_

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_entities.h"
#include "groundline/io/dds_pubsub.h"

namespace groundline::io {

struct DdsOutputsOptions {
  // An empty topic name is not published.
  std::string pose_topic = "rt/groundline/pose";
  std::string tf_topic = "rt/tf";
  std::string diagnostics_topic = "rt/diagnostics";
  std::string map_frame = "map";
  std::string odom_frame = "odom";

  // Ok if topic names are empty or start with "rt/", and frames are non-empty.
  core::Status Validate() const;
};

class DdsOutputs {
 public:
  static core::Result<DdsOutputs> Create(const DdsParticipant& participant,
                                         const DdsOutputsOptions& options);

  // T_map_base with its covariance (tangent space, (x, y, yaw); dds_convert.h).
  core::Status PublishPose(double stamp_s, const core::SE2& T_map_base,
                           const core::Matrix3& covariance) const;
  // The map -> odom correction, T_map_odom = T_map_base * T_odom_base^-1.
  core::Status PublishMapToOdom(double stamp_s, const core::SE2& T_map_odom) const;
  core::Status PublishDiagnostics(double stamp_s,
                                  const std::vector<DiagnosticEntry>& entries) const;

  // Waits up to `timeout` until every reliable reader has acknowledged what
  // was written (call before destroying the outputs at a clean shutdown, so
  // that the last pose is not lost in flight). False if some did not in time.
  bool WaitForAcknowledgements(std::chrono::milliseconds timeout) const;

  const DdsOutputsOptions& options() const { return options_; }

 private:
  DdsOutputs() = default;
  DdsOutputsOptions options_;
  std::optional<DdsPublisher<RosPoseWithCovarianceStamped>> pose_;
  std::optional<DdsPublisher<RosTfMessage>> tf_;
  std::optional<DdsPublisher<RosDiagnosticArray>> diagnostics_;
};

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_DDS_OUTPUTS_H_
