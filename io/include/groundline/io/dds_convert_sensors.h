// Conversions of sensor data between groundline and ROS 2 (stamps and
// headers as in dds_convert.h).
//
// LaserScan: ROS 2 marks a beam without a return by a range outside
// [range_min, range_max], +Inf for "nothing within range" and NaN for an
// invalid reading (REP-117); groundline uses kNoReturnRange_m (0). Outgoing
// no-returns are +Inf; incoming out-of-limit, Inf and NaN ranges become
// kNoReturnRange_m. angle_max = angle_min + (n - 1) angle_increment, as
// ROS drivers publish it. ROS ranges are float32: a range is rounded to
// ~1e-7 relative (0.1 um at 1 m), below the dataset's written precision.
// Images: only grey 8-bit images (mono8, CV_8UC1) are converted.
#ifndef GROUNDLINE_IO_DDS_CONVERT_SENSORS_H_
#define GROUNDLINE_IO_DDS_CONVERT_SENSORS_H_

#include <string>

#include <opencv2/core/mat.hpp>

#include "groundline/core/dataset_records.h"
#include "groundline/core/status.h"
#include "groundline/io/dds_types.h"

namespace groundline::io {

// time_increment and scan_time are 0 (beams treated as simultaneous, as in
// core::LaserScan) unless scan_time_s is given.
DdsSample<RosLaserScan> ToLaserScan(const core::LaserScan& scan, const std::string& frame_id,
                                    double scan_time_s = 0.0);
// Call ValidateLaserScan first. The stamp is header.stamp; intensities are
// kept if there is one per beam, dropped otherwise.
core::LaserScan FromLaserScan(const RosLaserScan& msg);

// A CV_8UC1 image (continuous or not) as mono8, step = width.
DdsSample<RosImage> ToMono8Image(const cv::Mat& grey, double stamp_s, const std::string& frame_id);
// A deep copy of a mono8 image; an error naming the field for any other
// encoding or a data size that disagrees with step * height (ValidateImage
// makes the same checks).
core::Result<cv::Mat> FromMono8Image(const RosImage& msg);

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_DDS_CONVERT_SENSORS_H_
