// AprilTag detection (libapriltag 3.3, family tag36h11) and the printed tag
// pattern, behind one RAII adapter (tag_detection.cc).
//
// Corner order. libapriltag reports the corners det->p[0..3] of the outer
// black square, counter-clockwise as seen in the image. In the tag's own
// frame, with the printed tag upright (pattern row 0 at the top), x to the
// right and y up, the corners are:
//   p[0] = (-s, -s)  bottom-left      p[1] = (+s, -s)  bottom-right
//   p[2] = (+s, +s)  top-right        p[3] = (-s, +s)  top-left
// with s = size_m / 2 (size_m: the edge of the outer black square).
// TagDetection::corners_px keeps this order (docs/tag_layout.md; the test
// TagDetection.CornerOrderMatchesThePrintedPattern checks it).
//
// Pixels follow camera_model.h: integer values at pixel centres.
// libapriltag 3.3 reports corners with the pixel centre at (+0.5, +0.5) (its
// line fit samples pixel (x, y) at x + 0.5, y + 0.5); DetectTags subtracts
// 0.5 so that the corners are in groundline's convention.
//
// Debian's 3.3 biases corners when quad_decimate > 1, hence the default 1.
//
// Thread-safety: DetectTags creates its own detector per call; it is safe to
// call concurrently.
#ifndef GROUNDLINE_CALIBRATION_TAG_DETECTION_H_
#define GROUNDLINE_CALIBRATION_TAG_DETECTION_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::calibration {

struct TagDetectorOptions {
  double quad_decimate = 1.0;  // 1: full resolution (no decimation corner bias)
  double quad_sigma = 0.0;     // Gaussian blur before segmentation, pixels
  bool refine_edges = true;    // snap the quad edges to the strongest gradient
  double decode_sharpening = 0.25;
  int max_bits_corrected = 1;         // reject codes with more bit errors
  double min_decision_margin = 20.0;  // reject weak decodes (grey levels)
  // Reject tags with a corner closer than this to the image border: libapriltag
  // extrapolates the edges of a tag cut by the border, misplacing its corners.
  double border_margin_px = 4.0;
  // A tag field has unique ids: keep only the strongest detection of an id
  // seen twice. false keeps every detection (photos may repeat an id).
  bool one_per_id = true;
  int threads = 1;

  core::Status Validate() const;
};

struct TagDetection {
  int id = 0;
  std::array<Eigen::Vector2d, 4> corners_px;  // the order of the file comment
  double decision_margin = 0.0;
  int bits_corrected = 0;
};

// Detects tag36h11 in an 8-bit grey image (row-major, row stride in bytes).
// Detections are sorted by id, then by the corners' mean u, then v; tags
// closer than border_margin_px to the image border are dropped; with
// one_per_id, an id seen twice in one image keeps the one with the larger
// decision margin. options must be valid (asserted).
std::vector<TagDetection> DetectTags(const std::uint8_t* pixels, int width_px, int height_px,
                                     int stride_bytes, const TagDetectorOptions& options = {});

// The printed pattern of tag36h11 tag `id`: total_width x total_width cells
// (10 x 10: a white outer ring, the black border ring, 6 x 6 data bits),
// row-major with row 0 at the top of the upright tag; 1 = black.
// width_at_border (8) cells span size_m.
struct TagPattern {
  int total_width = 0;
  int width_at_border = 0;
  std::vector<std::uint8_t> black;
  bool Black(int row, int col) const {
    return black[static_cast<std::size_t>(row) * total_width + col] != 0;
  }
};

// Fails for an id outside [0, Tag36h11Count()).
core::Result<TagPattern> Tag36h11Pattern(int id);
int Tag36h11Count();

// The corners of a tag in its own frame (metres, order of the file comment).
std::array<Eigen::Vector2d, 4> TagCornersInTagFrame(double size_m);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_TAG_DETECTION_H_
