#include "groundline/localization/atlas_accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "groundline/core/covariance.h"
#include "groundline/core/statistics.h"
#include "groundline/localization/floor_association.h"

namespace groundline::localization {
namespace {

LandmarkAccuracy Summarize(int built, const std::vector<double>& rho,
                           const std::vector<double>& alpha, const std::vector<double>& nees) {
  LandmarkAccuracy out;
  out.built = built;
  out.paired = static_cast<int>(rho.size());
  if (rho.empty()) return out;
  out.median_abs_rho_m = core::Median(rho);
  out.median_abs_alpha_rad = alpha.empty() ? 0.0 : core::Median(alpha);
  out.max_abs_rho_m = *std::max_element(rho.begin(), rho.end());
  const double bound = core::ChiSquareQuantile(2, 0.9973);
  out.within_3_sigma = static_cast<double>(std::count_if(nees.begin(), nees.end(),
                                                         [&](double v) { return v <= bound; })) /
                       static_cast<double>(nees.size());
  return out;
}

}  // namespace

AtlasAccuracy CompareAtlases(const Atlas& built, const Atlas& reference,
                             const AtlasAccuracyOptions& options) {
  AtlasAccuracy out;
  for (const bool faces : {false, true}) {
    std::vector<double> rho, alpha, nees;
    int n = 0;
    for (const AtlasLine& b : built.lines) {
      if (core::IsFaceKind(b.kind) != faces) continue;
      ++n;
      double best = std::numeric_limits<double>::infinity();
      Eigen::Vector2d error = Eigen::Vector2d::Zero();
      double offset = 0.0;
      const Eigen::Vector2d middle = 0.5 * (b.endpoint_a_m + b.endpoint_b_m);
      for (const AtlasLine& r : reference.lines) {
        if (core::IsFaceKind(r.kind) != faces || !ExtentsOverlap(b, r, options.extent_margin_m))
          continue;
        const Eigen::Vector2d e = perception::LineError(b.line_map, r.line_map);
        const double d = std::abs(perception::SignedDistance(r.line_map, middle));
        if (d > options.gate_rho_m || std::abs(e(1)) > options.gate_alpha_rad) continue;
        const double score = d / options.gate_rho_m + std::abs(e(1)) / options.gate_alpha_rad;
        if (score < best) best = score, error = e, offset = d;
      }
      if (!std::isfinite(best)) continue;
      rho.push_back(offset);
      alpha.push_back(std::abs(error(1)));
      nees.push_back(core::SquaredMahalanobis<2>(error, b.covariance));
    }
    (faces ? out.faces : out.floor_lines) = Summarize(n, rho, alpha, nees);
  }
  std::vector<double> distance, none, nees;
  for (const AtlasJunction& b : built.junctions) {
    double best = options.gate_junction_m;
    Eigen::Vector2d error = Eigen::Vector2d::Zero();
    bool found = false;
    for (const AtlasJunction& r : reference.junctions) {
      const Eigen::Vector2d e = b.point_m - r.point_m;
      if (e.norm() <= best) best = e.norm(), error = e, found = true;
    }
    if (!found) continue;
    distance.push_back(error.norm());
    nees.push_back(core::SquaredMahalanobis<2>(error, b.covariance));
  }
  out.junctions = Summarize(static_cast<int>(built.junctions.size()), distance, none, nees);
  return out;
}

}  // namespace groundline::localization
