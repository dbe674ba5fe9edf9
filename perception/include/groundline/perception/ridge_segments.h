// From ridge energy to straight segment candidates in the BEV (cell units):
// Otsu binarization of the ridge energy, non-maximum suppression across the
// ridge, progressive probabilistic Hough transform (cv::HoughLinesP; Matas,
// Galambos & Kittler 2000), and merging of collinear pieces (worn tape,
// dashed lines) into one segment.
//
// Coordinates are continuous BEV cell coordinates (col, row) as in
// bev_remap.h. Functions are pure and thread-safe.
#ifndef GROUNDLINE_PERCEPTION_RIDGE_SEGMENTS_H_
#define GROUNDLINE_PERCEPTION_RIDGE_SEGMENTS_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

#include "groundline/core/status.h"

namespace groundline::perception {

struct RidgeSegmentOptions {
  // Energy scale of the 8-bit histogram Otsu runs on: energies in [0, this]
  // map to 0..255 (larger values saturate). Ridge energy is in grey levels of
  // the sigma^2-normalized response (steerable_ridge.h).
  double otsu_energy_range = 64.0;
  // The threshold is Otsu clamped to [min_energy, max_energy]: without markings in view, Otsu
  // alone would split the concrete texture.
  double min_energy = 4.0;
  // .. and at most max_energy: one strong marking (a wide bar's edges) would
  // otherwise lift it above thin faint ones (8 mm joints) in the same frame.
  double max_energy = 5.0;
  // Anisotropy: cells with eigen_ratio above this are blobs, not ridges.
  double max_eigen_ratio = 0.35;
  // cv::HoughLinesP: accumulator votes, shortest segment, largest gap (cells).
  int hough_votes = 15;
  double hough_min_length_cells = 15.0;
  // A gap of 8: non-maximum suppression puts the centres of a ridge that runs
  // along the grid half a cell off the cell centres in runs of 5-20 on either
  // neighbouring cell, and HoughLinesP's walk along one pixel line must
  // bridge the runs on the other (with 4, a joint at y = 0.5 m in zone C and
  // dashes of the centre tape in zone A were missed whole).
  double hough_max_gap_cells = 8.0;
  // Merging collinear segments: direction within this, both endpoints of the
  // shorter within merge_offset_cells of the longer one's line, and at most
  // merge_gap_cells of empty line between them.
  double merge_angle_deg = 2.5;
  double merge_offset_cells = 2.0;
  double merge_gap_cells = 120.0;

  core::Status Validate() const;
};

// A straight piece in BEV cell coordinates.
struct RidgeSegment {
  Eigen::Vector2d a_cell = Eigen::Vector2d::Zero();
  Eigen::Vector2d b_cell = Eigen::Vector2d::Zero();
  double Length() const { return (b_cell - a_cell).norm(); }
};

// Otsu's threshold (0..255) of a 256-bin histogram (counts), the bin index t
// maximizing the between-class variance of {< = t} and {> t}. 0 when empty.
int OtsuThreshold(std::span<const double> histogram);

// The energy threshold of one image: (Otsu over the energies of the cells
// in mask (CV_8U, nonzero = use)) clamped to [min_energy, max_energy], in energy units.
double RidgeEnergyThreshold(const cv::Mat& energy, const cv::Mat& mask,
                            const RidgeSegmentOptions& options);

// The ridge centre mask (CV_8U, 255 on centres): energy > threshold, eigen_ratio
// <= max_eigen_ratio, inside mask, and energy not smaller than at both
// neighbours along the ridge normal (normal_rad: image angle, steerable_ridge.h;
// quantized to 0, 45, 90, 135 deg). energy, eigen_ratio, normal_rad: CV_32FC1.
void RidgeCentreMask(const cv::Mat& energy, const cv::Mat& eigen_ratio, const cv::Mat& normal_rad,
                     const cv::Mat& mask, double threshold, const RidgeSegmentOptions& options,
                     cv::Mat* centres);

// cv::HoughLinesP on the centre mask (1 cell, 1 deg resolution).
std::vector<RidgeSegment> HoughSegments(const cv::Mat& centres, const RidgeSegmentOptions& options);

// Merges collinear pieces (see the options), longest first, until no pair
// merges. A merged segment lies on the longest member's line and spans the
// projections of all members' endpoints.
std::vector<RidgeSegment> MergeCollinearSegments(std::vector<RidgeSegment> segments,
                                                 const RidgeSegmentOptions& options);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_RIDGE_SEGMENTS_H_
