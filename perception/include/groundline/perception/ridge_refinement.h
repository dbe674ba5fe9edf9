// Sub-pixel ridge centres along a segment candidate: at every cell along the
// segment the ridge energy is sampled (bilinear) across it at integer offsets
// -K..K cells; the largest sample and its two neighbours are fitted with a
// parabola, whose vertex is the centre:
//
//   delta = (E(-1) - E(+1)) / (2 (E(-1) - 2 E(0) + E(+1))),   |delta| <= 1/2,
//
// (the three-point peak interpolation). A sample is accepted when the maximum
// is interior (not at +-K), its energy is at least min_energy, and the
// Hessian's anisotropy and normal agree with a ridge along the segment.
// Coordinates: BEV cell coordinates (bev_remap.h). Pure and thread-safe.
#ifndef GROUNDLINE_PERCEPTION_RIDGE_REFINEMENT_H_
#define GROUNDLINE_PERCEPTION_RIDGE_REFINEMENT_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "groundline/perception/ridge_segments.h"

namespace groundline::perception {

struct RidgeRefinementOptions {
  int search_half_width_cells = 3;  // K
  // Sampling continues beyond both ends of the segment until this many
  // consecutive positions have no accepted centre.
  double extend_cells = 8.0;
  double max_eigen_ratio = 0.35;
  double max_normal_deviation_deg = 12.0;  // ridge normal vs the segment's normal
};

struct RidgeSample {
  Eigen::Vector2d centre_cell;  // sub-cell ridge centre
  double along_cell = 0.0;      // position along the segment from a_cell
  float energy = 0.0f;          // interpolated peak energy
  float width_cells = 0.0f;     // sqrt(E0 / |curvature|) of the parabola: the peak's width
};

struct RidgeImagesView {
  const cv::Mat* energy = nullptr;       // CV_32FC1
  const cv::Mat* eigen_ratio = nullptr;  // CV_32FC1
  const cv::Mat* normal_rad = nullptr;   // CV_32FC1, image angle in (-pi/2, pi/2]
};

// The accepted samples along segment, in order of along_cell; also the number
// of positions tried (for the support fraction) in *positions if not null.
std::vector<RidgeSample> RefineRidgeCentres(const RidgeImagesView& images,
                                            const RidgeSegment& segment, double min_energy,
                                            const RidgeRefinementOptions& options,
                                            int* positions = nullptr);

// Bilinear sample of a CV_32FC1 image at (col, row); 0 outside.
float SampleBilinear(const cv::Mat& image, double col, double row);

}  // namespace groundline::perception

#endif  // GROUNDLINE_PERCEPTION_RIDGE_REFINEMENT_H_
