// The libapriltag adapter: RAII around the detector, the family and the
// detections, and the family's printed pattern.
#include "groundline/calibration/tag_detection.h"

// common/image_u8.h and tag36h11.h lack extern "C" guards in 3.3.
extern "C" {
#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/common/zarray.h>
#include <apriltag/tag36h11.h>
}

#include <algorithm>
#include <cassert>
#include <memory>
#include <string>
#include <tuple>

namespace groundline::calibration {
namespace {

// libapriltag reports pixel (x, y) centred at (x + 0.5, y + 0.5); see the header.
constexpr double kApriltagPixelOffset = 0.5;

struct FamilyDeleter {
  void operator()(apriltag_family_t* f) const { tag36h11_destroy(f); }
};
struct DetectorDeleter {
  void operator()(apriltag_detector_t* d) const { apriltag_detector_destroy(d); }
};
struct DetectionsDeleter {
  void operator()(zarray_t* z) const { apriltag_detections_destroy(z); }
};
struct ImageDeleter {
  void operator()(image_u8_t* im) const { image_u8_destroy(im); }
};
using Family = std::unique_ptr<apriltag_family_t, FamilyDeleter>;

}  // namespace

core::Status TagDetectorOptions::Validate() const {
  if (!(quad_decimate >= 1.0 && quad_decimate <= 8.0)) {
    return core::Status::Error("TagDetectorOptions.quad_decimate: expected 1..8");
  }
  if (!(quad_sigma >= 0.0 && quad_sigma <= 5.0)) {
    return core::Status::Error("TagDetectorOptions.quad_sigma: expected 0..5 px");
  }
  if (!(decode_sharpening >= 0.0 && decode_sharpening <= 2.0)) {
    return core::Status::Error("TagDetectorOptions.decode_sharpening: expected 0..2");
  }
  if (max_bits_corrected < 0 || max_bits_corrected > 3) {
    return core::Status::Error("TagDetectorOptions.max_bits_corrected: expected 0..3");
  }
  if (!(min_decision_margin >= 0.0)) {
    return core::Status::Error("TagDetectorOptions.min_decision_margin: expected >= 0");
  }
  if (!(border_margin_px >= 0.0)) {
    return core::Status::Error("TagDetectorOptions.border_margin_px: expected >= 0");
  }
  if (threads < 1 || threads > 64) {
    return core::Status::Error("TagDetectorOptions.threads: expected 1..64");
  }
  return core::Status::Ok();
}

std::vector<TagDetection> DetectTags(const std::uint8_t* pixels, int width_px, int height_px,
                                     int stride_bytes, const TagDetectorOptions& options) {
  assert(options.Validate().ok());
  assert(pixels != nullptr && width_px > 0 && height_px > 0 && stride_bytes >= width_px);
  Family family(tag36h11_create());
  std::unique_ptr<apriltag_detector_t, DetectorDeleter> detector(apriltag_detector_create());
  apriltag_detector_add_family_bits(detector.get(), family.get(), options.max_bits_corrected);
  detector->quad_decimate = static_cast<float>(options.quad_decimate);
  detector->quad_sigma = static_cast<float>(options.quad_sigma);
  detector->refine_edges = options.refine_edges;
  detector->decode_sharpening = options.decode_sharpening;
  detector->nthreads = options.threads;

  // libapriltag wants its own (aligned) buffer.
  std::unique_ptr<image_u8_t, ImageDeleter> image(
      image_u8_create(static_cast<unsigned>(width_px), static_cast<unsigned>(height_px)));
  for (int v = 0; v < height_px; ++v) {
    std::copy_n(pixels + static_cast<std::size_t>(v) * stride_bytes, width_px,
                image->buf + static_cast<std::size_t>(v) * image->stride);
  }
  std::unique_ptr<zarray_t, DetectionsDeleter> found(
      apriltag_detector_detect(detector.get(), image.get()));

  std::vector<TagDetection> out;
  for (int i = 0; i < zarray_size(found.get()); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(found.get(), i, &det);
    if (det->decision_margin < options.min_decision_margin) continue;
    TagDetection d;
    d.id = det->id;
    d.decision_margin = det->decision_margin;
    d.bits_corrected = det->hamming;
    for (int k = 0; k < 4; ++k) {
      d.corners_px[k] =
          Eigen::Vector2d(det->p[k][0] - kApriltagPixelOffset, det->p[k][1] - kApriltagPixelOffset);
    }
    bool inside = true;
    for (const Eigen::Vector2d& c : d.corners_px) {
      inside = inside && c.x() >= options.border_margin_px && c.y() >= options.border_margin_px &&
               c.x() <= width_px - 1 - options.border_margin_px &&
               c.y() <= height_px - 1 - options.border_margin_px;
    }
    if (inside) out.push_back(d);
  }
  const auto key = [](const TagDetection& t) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& c : t.corners_px) mean += c / 4.0;
    return std::make_tuple(t.id, mean.x(), mean.y());
  };
  std::sort(out.begin(), out.end(),
            [&](const TagDetection& a, const TagDetection& b) { return key(a) < key(b); });
  if (options.one_per_id) {
    std::vector<TagDetection> strongest;
    for (const TagDetection& d : out) {
      if (!strongest.empty() && strongest.back().id == d.id) {
        if (strongest.back().decision_margin < d.decision_margin) strongest.back() = d;
      } else {
        strongest.push_back(d);
      }
    }
    out = std::move(strongest);
  }
  return out;
}

int Tag36h11Count() {
  Family family(tag36h11_create());
  return static_cast<int>(family->ncodes);
}

core::Result<TagPattern> Tag36h11Pattern(int id) {
  Family family(tag36h11_create());
  if (id < 0 || id >= static_cast<int>(family->ncodes)) {
    return core::Status::Error("tag36h11 has ids 0.." + std::to_string(family->ncodes - 1) +
                               ", got " + std::to_string(id));
  }
  std::unique_ptr<image_u8_t, ImageDeleter> image(apriltag_to_image(family.get(), id));
  TagPattern p;
  p.total_width = family->total_width;
  p.width_at_border = family->width_at_border;
  assert(image->width == p.total_width && image->height == p.total_width);
  p.black.resize(static_cast<std::size_t>(p.total_width) * p.total_width);
  for (int r = 0; r < p.total_width; ++r) {
    for (int c = 0; c < p.total_width; ++c) {
      p.black[static_cast<std::size_t>(r) * p.total_width + c] =
          image->buf[static_cast<std::size_t>(r) * image->stride + c] < 128 ? 1 : 0;
    }
  }
  return p;
}

std::array<Eigen::Vector2d, 4> TagCornersInTagFrame(double size_m) {
  const double s = 0.5 * size_m;
  return {Eigen::Vector2d(-s, -s), Eigen::Vector2d(s, -s), Eigen::Vector2d(s, s),
          Eigen::Vector2d(-s, s)};
}

}  // namespace groundline::calibration
