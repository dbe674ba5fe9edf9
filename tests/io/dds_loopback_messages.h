// The messages the loopback test's publisher process sends, generated from
// their index so that the subscribing test can check every field it receives.
#ifndef GROUNDLINE_TESTS_IO_DDS_LOOPBACK_MESSAGES_H_
#define GROUNDLINE_TESTS_IO_DDS_LOOPBACK_MESSAGES_H_

#include <opencv2/core/mat.hpp>

#include "groundline/core/dataset_records.h"
#include "groundline/io/dds_convert.h"

namespace groundline::io::testing {

inline constexpr int kLoopbackMessages = 25;  // per topic, before the bad ones

inline double LoopbackStamp(int i) { return 1000.0 + 0.1 * i; }

inline PlanarOdometry LoopbackOdometry(int i) {
  PlanarOdometry o;
  o.stamp_s = LoopbackStamp(i);
  o.T_odom_base = core::SE2(0.5 * i, -0.25 * i, 0.01 * i);
  o.covariance = core::Vector3(1e-4 * (i + 1), 2e-4 * (i + 1), 1e-5 * (i + 1)).asDiagonal();
  o.forward_velocity_mps = 0.5;
  o.yaw_rate_radps = 0.1;
  return o;
}

inline double LoopbackLeftWheel_rad(int i) { return 0.3 * i; }
inline double LoopbackRightWheel_rad(int i) { return 0.2 * i + 0.01 * i * i; }

inline core::LaserScan LoopbackScan(int i) {
  core::LaserScan s;
  s.stamp_s = LoopbackStamp(i) + 0.05;
  s.angle_min_rad = -1.5;
  s.angle_increment_rad = 0.5;
  s.range_min_m = 0.1;
  s.range_max_m = 10.0;
  s.ranges_m = {1.0 + 0.25 * i, core::kNoReturnRange_m, 0.5, 2.0, 9.5 - 0.125 * i, 3.0, 4.0};
  return s;
}

inline cv::Mat LoopbackImage(int i) {
  cv::Mat grey(3, 4, CV_8UC1);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c)
      grey.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(i + 10 * r + c);
  }
  return grey;
}

}  // namespace groundline::io::testing

#endif  // GROUNDLINE_TESTS_IO_DDS_LOOPBACK_MESSAGES_H_
