// QoS presets as ROS 2 Humble uses them (rmw_qos_profile_* of rmw/qos_profiles.h
// and the profiles of tf2_ros and nav2), so that groundline's readers and
// writers match ROS 2 nodes:
//   kSensorData  best effort, volatile,        keep last 5    (rmw_qos_profile_sensor_data)
//   kDefault     reliable,    volatile,        keep last 10   (rmw_qos_profile_default)
//   kPoseOutput  reliable,    transient local, keep last 1    (nav2 AMCL's amcl_pose)
//   kTf          reliable,    volatile,        keep last 100  (tf2_ros TransformBroadcaster)
//   kTfStatic    reliable,    transient local, keep last 1    (tf2_ros StaticTransformBroadcaster)
//   kLossless    reliable,    volatile,        keep all       (not a ROS profile: tests and
//                recording, where a slow reader must block the writer rather than lose data)
// A best-effort reader matches any writer; a reliable reader does not match a
// best-effort writer, and a transient-local reader does not match a volatile
// writer (DDS request/offer rules).
#ifndef GROUNDLINE_IO_DDS_QOS_H_
#define GROUNDLINE_IO_DDS_QOS_H_

#include <memory>

#include <dds/dds.h>

namespace groundline::io {

enum class QosPreset { kSensorData, kDefault, kPoseOutput, kTf, kTfStatic, kLossless };

const char* QosPresetName(QosPreset preset);

struct DdsQosDeleter {
  void operator()(dds_qos_t* qos) const { dds_delete_qos(qos); }
};
using DdsQos = std::unique_ptr<dds_qos_t, DdsQosDeleter>;

// A new QoS object holding the preset (never null).
DdsQos MakeQos(QosPreset preset);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_DDS_QOS_H_
