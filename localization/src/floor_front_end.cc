#include "groundline/localization/floor_front_end.h"

#include <memory>
#include <string>

namespace groundline::localization {

core::Status FloorFrontEndOptions::Validate() const {
  if (core::Status s = remap.Validate(); !s.ok()) return s.WithContext("remap");
  if (core::Status s = extractor.Validate(); !s.ok()) return s.WithContext("extractor");
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
                               " px (the camera model's imager), got " +
                               std::to_string(grey.cols) + "x" + std::to_string(grey.rows));
  }
  remap_->Apply(grey, bev);
  return ObservationsFromExtraction(stamp_s, extractor_->Extract(*bev));
}

}  // namespace groundline::localization
