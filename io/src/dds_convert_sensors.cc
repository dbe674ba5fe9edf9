#include "groundline/io/dds_convert_sensors.h"

#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>

#include "groundline/io/dds_convert.h"

namespace groundline::io {

DdsSample<RosLaserScan> ToLaserScan(const core::LaserScan& scan, const std::string& frame_id,
                                    double scan_time_s) {
  DdsSample<RosLaserScan> out;
  RosLaserScan& m = out.msg();
  SetHeader(scan.stamp_s, frame_id, &m.header);
  const std::size_t n = scan.ranges_m.size();
  m.angle_min = static_cast<float>(scan.angle_min_rad);
  m.angle_max = static_cast<float>(n == 0 ? scan.angle_min_rad : scan.BeamAngle_rad(n - 1));
  m.angle_increment = static_cast<float>(scan.angle_increment_rad);
  m.time_increment = 0.0f;
  m.scan_time = static_cast<float>(scan_time_s);
  m.range_min = static_cast<float>(scan.range_min_m);
  m.range_max = static_cast<float>(scan.range_max_m);
  DdsAllocSequence(&m.ranges, static_cast<std::uint32_t>(n));
  for (std::size_t i = 0; i < n; ++i) {
    m.ranges._buffer[i] = scan.IsReturn(i) ? static_cast<float>(scan.ranges_m[i])
                                           : std::numeric_limits<float>::infinity();
  }
  DdsAllocSequence(&m.intensities, static_cast<std::uint32_t>(scan.intensities.size()));
  for (std::size_t i = 0; i < scan.intensities.size(); ++i) {
    m.intensities._buffer[i] = static_cast<float>(scan.intensities[i]);
  }
  return out;
}

core::LaserScan FromLaserScan(const RosLaserScan& msg) {
  core::LaserScan scan;
  scan.stamp_s = FromRosTime(msg.header.stamp);
  scan.angle_min_rad = msg.angle_min;
  scan.angle_increment_rad = msg.angle_increment;
  scan.range_min_m = msg.range_min;
  scan.range_max_m = msg.range_max;
  scan.ranges_m.resize(msg.ranges._length);
  for (std::uint32_t i = 0; i < msg.ranges._length; ++i) {
    const float r = msg.ranges._buffer[i];
    // NaN and Inf fail both comparisons' complements: no return.
    const bool valid = r >= msg.range_min && r <= msg.range_max;
    scan.ranges_m[i] = valid ? static_cast<double>(r) : core::kNoReturnRange_m;
  }
  if (msg.intensities._length == msg.ranges._length) {
    scan.intensities.assign(msg.intensities._buffer,
                            msg.intensities._buffer + msg.intensities._length);
  }
  return scan;
}

DdsSample<RosImage> ToMono8Image(const cv::Mat& grey, double stamp_s, const std::string& frame_id) {
  assert(grey.type() == CV_8UC1);
  DdsSample<RosImage> out;
  RosImage& m = out.msg();
  SetHeader(stamp_s, frame_id, &m.header);
  m.height = static_cast<std::uint32_t>(grey.rows);
  m.width = static_cast<std::uint32_t>(grey.cols);
  m.encoding = DdsStringDup("mono8");
  m.is_bigendian = 0;
  m.step = m.width;
  DdsAllocSequence(&m.data, m.height * m.step);
  for (int r = 0; r < grey.rows; ++r) {
    std::memcpy(m.data._buffer + static_cast<std::size_t>(r) * m.step, grey.ptr<std::uint8_t>(r),
                m.width);
  }
  return out;
}

core::Result<cv::Mat> FromMono8Image(const RosImage& msg) {
  const std::string encoding = msg.encoding != nullptr ? msg.encoding : "";
  if (encoding != "mono8") {
    return core::Status::Error("sensor_msgs/Image: field 'encoding': expected 'mono8', got '" +
                               encoding + "'");
  }
  if (msg.step < msg.width ||
      static_cast<std::uint64_t>(msg.step) * msg.height != msg.data._length) {
    return core::Status::Error(
        "sensor_msgs/Image: field 'data': " + std::to_string(msg.data._length) +
        " bytes, expected step " + std::to_string(msg.step) + " x height " +
        std::to_string(msg.height) + " with step >= width " + std::to_string(msg.width));
  }
  cv::Mat grey(static_cast<int>(msg.height), static_cast<int>(msg.width), CV_8UC1);
  for (std::uint32_t r = 0; r < msg.height; ++r) {
    std::memcpy(grey.ptr<std::uint8_t>(static_cast<int>(r)),
                msg.data._buffer + static_cast<std::size_t>(r) * msg.step, msg.width);
  }
  return grey;
}

}  // namespace groundline::io
