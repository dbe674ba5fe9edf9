#include "rendered_bev.h"

#include <cstdint>
#include <utility>

namespace groundline::perception {

cv::Mat RenderBev(const BevGrid& grid, const Floor& floor, double noise_dn, unsigned seed) {
  cv::Mat bev(grid.rows(), grid.cols(), CV_8U);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_dn);
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      double sum = 0.0;
      for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
          sum += floor(grid.FloorPointOfCell({c + i / 3.0, r + j / 3.0}));
        }
      }
      bev.at<std::uint8_t>(r, c) = cv::saturate_cast<std::uint8_t>(sum / 9.0 + noise(rng));
    }
  }
  return bev;
}

LineExtractor MakeExtractor(const BevGrid& grid, const LineExtractorOptions& options,
                            std::optional<Eigen::Vector2d> camera_foot_m) {
  const cv::Mat valid(grid.rows(), grid.cols(), CV_8U, cv::Scalar(255));
  const cv::Mat J(grid.rows(), grid.cols(), CV_64FC4, cv::Scalar(0.002, 0.0, 0.0, 0.002));
  return LineExtractor(grid, valid, J, options, camera_foot_m);
}

double Texture(const Eigen::Vector2d& p, unsigned seed) {
  const auto hash = [seed](long i, long j) {
    std::uint32_t h = static_cast<std::uint32_t>(i * 73856093L ^ j * 19349663L ^ seed * 83492791L);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return (h & 0xffff) / 65535.0;
  };
  const auto noise = [&](double x, double y) {
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    const long i = static_cast<long>(fx), j = static_cast<long>(fy);
    const double a = hash(i, j), b = hash(i + 1, j), c = hash(i, j + 1), d = hash(i + 1, j + 1);
    return (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty;
  };
  return 1.0 + 0.16 * (noise(p.x() / 0.04, p.y() / 0.04) - 0.5) +
         0.08 * (noise(p.x() / 0.01, p.y() / 0.01) - 0.5);
}

Floor Paint(std::vector<Tape> tapes, double concrete) {
  return [tapes = std::move(tapes), concrete](const Eigen::Vector2d& p) {
    for (const Tape& t : tapes) {
      if (core::DistanceToSegment(p, t.a, t.b) <= 0.5 * t.width_m) return t.grey;
    }
    return concrete;
  };
}

}  // namespace groundline::perception
