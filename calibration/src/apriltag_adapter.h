// The one place groundline touches libapriltag's C API (Debian libapriltag
// 3.3): RAII ownership of the family, the detector, detections and images.
// Private to the calibration module.
#ifndef GROUNDLINE_CALIBRATION_SRC_APRILTAG_ADAPTER_H_
#define GROUNDLINE_CALIBRATION_SRC_APRILTAG_ADAPTER_H_

extern "C" {
#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
}

#include <cstdlib>
#include <memory>

namespace groundline::calibration::apriltag_adapter {

struct FamilyDeleter {
  void operator()(apriltag_family_t* family) const noexcept { tag36h11_destroy(family); }
};
using FamilyPtr = std::unique_ptr<apriltag_family_t, FamilyDeleter>;
inline FamilyPtr Tag36h11() { return FamilyPtr(tag36h11_create()); }

struct DetectorDeleter {
  void operator()(apriltag_detector_t* detector) const noexcept {
    apriltag_detector_destroy(detector);
  }
};
using DetectorPtr = std::unique_ptr<apriltag_detector_t, DetectorDeleter>;

struct DetectionsDeleter {
  void operator()(zarray_t* detections) const noexcept { apriltag_detections_destroy(detections); }
};
using DetectionsPtr = std::unique_ptr<zarray_t, DetectionsDeleter>;

// Debian's libapriltag.so does not export image_u8_destroy; an image_u8_t it
// returns (apriltag_to_image) is two calloc'ed blocks, the struct and buf,
// which is exactly what image_u8_destroy frees.
struct ImageDeleter {
  void operator()(image_u8_t* image) const noexcept {
    if (image == nullptr) return;
    std::free(image->buf);
    std::free(image);
  }
};
using ImagePtr = std::unique_ptr<image_u8_t, ImageDeleter>;

}  // namespace groundline::calibration::apriltag_adapter

#endif  // GROUNDLINE_CALIBRATION_SRC_APRILTAG_ADAPTER_H_
