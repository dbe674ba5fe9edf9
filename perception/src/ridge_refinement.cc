// Sub-pixel ridge centres by three-point parabolic peak interpolation
// (ridge_refinement.h).
#include "groundline/perception/ridge_refinement.h"

#include <cmath>
#include <numbers>

namespace groundline::perception {

float SampleBilinear(const cv::Mat& image, double col, double row) {
  if (!(col >= 0.0 && row >= 0.0 && col <= image.cols - 1 && row <= image.rows - 1)) return 0.0f;
  const int c0 = std::min(static_cast<int>(col), image.cols - 2);
  const int r0 = std::min(static_cast<int>(row), image.rows - 2);
  const auto fc = static_cast<float>(col - c0);
  const auto fr = static_cast<float>(row - r0);
  const float* p0 = image.ptr<float>(r0) + c0;
  const float* p1 = image.ptr<float>(r0 + 1) + c0;
  return (1 - fr) * ((1 - fc) * p0[0] + fc * p0[1]) + fr * ((1 - fc) * p1[0] + fc * p1[1]);
}

std::vector<RidgeSample> RefineRidgeCentres(const RidgeImagesView& images,
                                            const RidgeSegment& segment, double min_energy,
                                            const RidgeRefinementOptions& options, int* positions) {
  const cv::Mat& energy = *images.energy;
  const Eigen::Vector2d d = (segment.b_cell - segment.a_cell).normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  const double length = segment.Length();
  const int k_max = options.search_half_width_cells;
  const double cos_max_dev = std::cos(options.max_normal_deviation_deg * std::numbers::pi / 180.0);
  std::vector<float> profile(2 * k_max + 1);
  // One position: the sub-cell centre across the segment at s, if accepted.
  auto sample_at = [&](double s, RidgeSample* sample) {
    const Eigen::Vector2d p = segment.a_cell + s * d;
    int best = 0;
    for (int k = -k_max; k <= k_max; ++k) {
      const Eigen::Vector2d q = p + k * n;
      profile[k + k_max] = SampleBilinear(energy, q.x(), q.y());
      if (profile[k + k_max] > profile[best]) best = k + k_max;
    }
    if (best == 0 || best == 2 * k_max) return false;
    const double e_minus = profile[best - 1], e0 = profile[best], e_plus = profile[best + 1];
    if (e0 < min_energy) return false;
    const double curvature = e_minus - 2.0 * e0 + e_plus;
    if (!(curvature < 0.0)) return false;
    const double delta = 0.5 * (e_minus - e_plus) / curvature;
    const Eigen::Vector2d centre = p + (best - k_max + delta) * n;
    const int col = static_cast<int>(std::lround(centre.x()));
    const int row = static_cast<int>(std::lround(centre.y()));
    if (col < 0 || row < 0 || col >= energy.cols || row >= energy.rows) return false;
    if (images.eigen_ratio->at<float>(row, col) > options.max_eigen_ratio) return false;
    const double angle = images.normal_rad->at<float>(row, col);
    if (std::abs(std::cos(angle) * n.x() + std::sin(angle) * n.y()) < cos_max_dev) return false;
    sample->centre_cell = centre;
    sample->along_cell = s;
    sample->energy =
        static_cast<float>(e0 - 0.125 * (e_minus - e_plus) * (e_minus - e_plus) / curvature);
    sample->width_cells = static_cast<float>(std::sqrt(2.0 * e0 / -curvature));
    return true;
  };
  std::vector<RidgeSample> samples;
  int tried = 0;
  RidgeSample sample;
  // Before the segment: walk back until extend_cells consecutive misses.
  std::vector<RidgeSample> before;
  for (double s = -1.0, misses = 0; misses < options.extend_cells; s -= 1.0) {
    ++tried;
    if (sample_at(s, &sample)) {
      before.push_back(sample);
      misses = 0;
    } else {
      ++misses;
    }
  }
  samples.assign(before.rbegin(), before.rend());
  double misses = 0;
  for (double s = 0.0; s <= length || misses < options.extend_cells; s += 1.0) {
    ++tried;
    if (sample_at(s, &sample)) {
      samples.push_back(sample);
      misses = 0;
    } else {
      ++misses;
    }
  }
  // Positions tried beyond the last accepted sample at either end do not count.
  tried -= static_cast<int>(2 * options.extend_cells);
  if (positions != nullptr) *positions = tried;
  return samples;
}

}  // namespace groundline::perception
