#include "groundline/io/dds_qos.h"

namespace groundline::io {

const char* QosPresetName(QosPreset preset) {
  switch (preset) {
    case QosPreset::kSensorData:
      return "sensor data";
    case QosPreset::kDefault:
      return "default";
    case QosPreset::kPoseOutput:
      return "pose output";
    case QosPreset::kTf:
      return "tf";
    case QosPreset::kTfStatic:
      return "tf_static";
    case QosPreset::kLossless:
      return "lossless";
  }
  return "?";
}

DdsQos MakeQos(QosPreset preset) {
  DdsQos qos(dds_create_qos());
  // ROS 2 leaves the reliable blocking time at rmw's 100 ms default.
  const dds_duration_t max_blocking = DDS_MSECS(100);
  switch (preset) {
    case QosPreset::kSensorData:
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 5);
      break;
    case QosPreset::kDefault:
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, max_blocking);
      dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 10);
      break;
    case QosPreset::kPoseOutput:
    case QosPreset::kTfStatic:
      // A late joiner (rviz, a planner started later) gets the last pose at once.
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, max_blocking);
      dds_qset_durability(qos.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 1);
      break;
    case QosPreset::kTf:
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, max_blocking);
      dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 100);
      break;
    case QosPreset::kLossless:
      dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
      dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
      dds_qset_history(qos.get(), DDS_HISTORY_KEEP_ALL, 0);
      break;
  }
  return qos;
}

}  // namespace groundline::io
