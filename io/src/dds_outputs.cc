#include "groundline/io/dds_outputs.h"

#include <utility>

namespace groundline::io {
namespace {

bool IsRtTopic(const std::string& name) { return name.empty() || name.rfind("rt/", 0) == 0; }

template <typename T>
core::Status MaybeCreate(const DdsParticipant& participant, const std::string& topic, QosPreset qos,
                         std::optional<DdsPublisher<T>>* out) {
  if (topic.empty()) return core::Status::Ok();
  core::Result<DdsPublisher<T>> pub = DdsPublisher<T>::Create(participant, topic, qos);
  if (!pub.ok()) return pub.status();
  out->emplace(std::move(*pub));
  return core::Status::Ok();
}

}  // namespace

core::Status DdsOutputsOptions::Validate() const {
  for (const std::string* t : {&pose_topic, &tf_topic, &diagnostics_topic}) {
    if (!IsRtTopic(*t)) {
      return core::Status::Error("DdsOutputsOptions: topic '" + *t +
                                 "' must start with 'rt/' (ROS 2 topic prefix) or be empty");
    }
  }
  if (map_frame.empty() || odom_frame.empty()) {
    return core::Status::Error("DdsOutputsOptions: map_frame and odom_frame must be non-empty");
  }
  return core::Status::Ok();
}

core::Result<DdsOutputs> DdsOutputs::Create(const DdsParticipant& participant,
                                            const DdsOutputsOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  DdsOutputs out;
  out.options_ = options;
  if (core::Status s =
          MaybeCreate(participant, options.pose_topic, QosPreset::kPoseOutput, &out.pose_);
      !s.ok()) {
    return s;
  }
  if (core::Status s = MaybeCreate(participant, options.tf_topic, QosPreset::kTf, &out.tf_);
      !s.ok()) {
    return s;
  }
  if (core::Status s = MaybeCreate(participant, options.diagnostics_topic, QosPreset::kDefault,
                                   &out.diagnostics_);
      !s.ok()) {
    return s;
  }
  return out;
}

core::Status DdsOutputs::PublishPose(double stamp_s, const core::SE2& T_map_base,
                                     const core::Matrix3& covariance) const {
  if (!pose_) return core::Status::Ok();
  PlanarPoseStamped pose;
  pose.stamp_s = stamp_s;
  pose.frame_id = options_.map_frame;
  pose.T_frame_base = T_map_base;
  pose.covariance = covariance;
  return pose_->Write(ToPoseWithCovarianceStamped(pose).msg());
}

core::Status DdsOutputs::PublishMapToOdom(double stamp_s, const core::SE2& T_map_odom) const {
  if (!tf_) return core::Status::Ok();
  return tf_->Write(
      ToTfMessage({{stamp_s, options_.map_frame, options_.odom_frame, T_map_odom}}).msg());
}

core::Status DdsOutputs::PublishDiagnostics(double stamp_s,
                                            const std::vector<DiagnosticEntry>& entries) const {
  if (!diagnostics_) return core::Status::Ok();
  return diagnostics_->Write(ToDiagnosticArray(stamp_s, entries).msg());
}

bool DdsOutputs::WaitForAcknowledgements(std::chrono::milliseconds timeout) const {
  const dds_duration_t ns = DDS_MSECS(timeout.count());
  bool all = true;
  for (const DdsEntity* w : {pose_ ? &pose_->writer() : nullptr, tf_ ? &tf_->writer() : nullptr,
                             diagnostics_ ? &diagnostics_->writer() : nullptr}) {
    if (w != nullptr && dds_wait_for_acks(w->get(), ns) != DDS_RETCODE_OK) all = false;
  }
  return all;
}

}  // namespace groundline::io
