#include "groundline/localization/floor_front_end.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

namespace groundline::localization {

core::Status FloorFrontEndOptions::Validate() const {
  if (core::Status s = remap.Validate(); !s.ok()) return s.WithContext("remap");
  if (core::Status s = extractor.Validate(); !s.ok()) return s.WithContext("extractor");
  if (!(min_frame_stddev >= 0.0 && min_frame_stddev < 128.0)) {
    return core::Status::Error("min_frame_stddev: expected 0..128 grey levels");
  }
  return core::Status::Ok();
}

core::Result<FloorFrontEnd> FloorFrontEnd::Create(const calibration::CameraModel& camera,
                                                  const calibration::CameraMount& mount,
                                                  const FloorFrontEndOptions& options) {
  if (core::Status s = options.Validate(); !s.ok()) return s.WithContext("floor front end");
  perception::BevRemap::Options remap_options = options.remap;
  if (options.grid_from_footprint) {
    remap_options.grid = perception::FloorFootprintGrid(camera, mount, options.remap.grid.cell_m);
  }
  FloorFrontEnd front_end;
  auto remap = std::make_shared<perception::BevRemap>(camera, mount, remap_options);
  if (cv::countNonZero(remap->valid_mask()) == 0) {
    return core::Status::Error(
        "floor front end: the camera sees none of the bird's-eye grid's floor (check the "
        "mount's height and pitch, or the grid extent)");
  }
  front_end.extractor_ = std::make_shared<perception::LineExtractor>(*remap, options.extractor);
  front_end.remap_ = std::move(remap);
  front_end.width_px_ = camera.width_px();
  front_end.height_px_ = camera.height_px();
  front_end.min_frame_stddev_ = options.min_frame_stddev;
  return front_end;
}

core::Result<ConvertedObservations> FloorFrontEnd::Observe(const cv::Mat& grey,
                                                           double stamp_s) const {
  cv::Mat bev;
  return Observe(grey, stamp_s, &bev);
}

core::Result<ConvertedObservations> FloorFrontEnd::Observe(const cv::Mat& grey, double stamp_s,
                                                           cv::Mat* bev) const {
  if (grey.empty() || grey.type() != CV_8UC1) {
    return core::Status::Error("camera frame at " + std::to_string(stamp_s) +
                               " s: expected an 8-bit grey image, got an empty or other-typed one");
  }
  if (grey.cols != width_px_ || grey.rows != height_px_) {
    return core::Status::Error("camera frame at " + std::to_string(stamp_s) + " s: expected " +
                               std::to_string(width_px_) + "x" + std::to_string(height_px_) +
                               " px (the camera model's imager), got " + std::to_string(grey.cols) +
                               "x" + std::to_string(grey.rows));
  }
  if (min_frame_stddev_ > 0.0) {
    // Every 16th pixel of every 16th row: a blank frame shows in any sample.
    double sum = 0.0, sum2 = 0.0;
    long n = 0;
    for (int r = 0; r < grey.rows; r += 16) {
      const std::uint8_t* row = grey.ptr<std::uint8_t>(r);
      for (int c = 0; c < grey.cols; c += 16, ++n) {
        sum += row[c];
        sum2 += static_cast<double>(row[c]) * row[c];
      }
    }
    const double mean = sum / static_cast<double>(n);
    const double stddev = std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean));
    if (stddev < min_frame_stddev_) {
      return core::Status::Error("camera frame at " + std::to_string(stamp_s) +
                                 " s: blank (grey level " + std::to_string(static_cast<int>(mean)) +
                                 ", spread " + std::to_string(stddev) + " < " +
                                 std::to_string(min_frame_stddev_) + "): covered or failed camera");
    }
  }
  remap_->Apply(grey, bev);
  return ObservationsFromExtraction(stamp_s, extractor_->Extract(*bev));
}

}  // namespace groundline::localization
