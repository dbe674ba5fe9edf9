#include "groundline/sim/floor_line_observations.h"

#include <Eigen/Cholesky>
#include <cassert>
#include <optional>
#include <random>

#include "groundline/core/random_draws.h"

namespace groundline::sim {
namespace {

// Clips the segment a-b to the box [x0, x1] x [y0, y1] (Liang-Barsky).
std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> Clip(const Eigen::Vector2d& a,
                                                                const Eigen::Vector2d& b, double x0,
                                                                double x1, double y0, double y1) {
  const Eigen::Vector2d d = b - a;
  double t0 = 0.0;
  double t1 = 1.0;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - x0, x1 - a.x(), a.y() - y0, y1 - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return std::nullopt;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return std::nullopt;
  }
  return std::make_pair(Eigen::Vector2d(a + t0 * d), Eigen::Vector2d(a + t1 * d));
}

}  // namespace

core::Status FloorObservationOptions::Validate() const {
  if (!(min_ahead_m >= 0.0 && max_ahead_m > min_ahead_m)) {
    return core::Status::Error("expected 0 <= min_ahead_m < max_ahead_m");
  }
  if (!(half_width_m > 0.0)) return core::Status::Error("half_width_m must be > 0");
  if (!(min_length_m > 0.0)) return core::Status::Error("min_length_m must be > 0");
  if (!(endpoint_sigma_m > 0.0)) return core::Status::Error("endpoint_sigma_m must be > 0");
  if (!(junction_sigma_m > 0.0)) return core::Status::Error("junction_sigma_m must be > 0");
  return core::Status::Ok();
}

FloorObservationSimulator::FloorObservationSimulator(const core::FloorMap& map,
                                                     const FloorObservationOptions& options)
    : options_(options),
      segments_(localization::MarkingSegments(map)),
      junctions_(localization::MarkingJunctions(map, localization::AtlasFromFloorMapOptions())),
      rng_(options.seed) {
  assert(options.Validate().ok());
  localization::FloorView view;
  view.polygon_base_m = {{options.min_ahead_m, -options.half_width_m},
                         {options.max_ahead_m, -options.half_width_m},
                         {options.max_ahead_m, options.half_width_m},
                         {options.min_ahead_m, options.half_width_m}};
  view_ = std::make_shared<const localization::FloorView>(std::move(view));
}

localization::FloorObservations FloorObservationSimulator::Observe(
    double stamp_s, const core::SE2& T_map_base_true) {
  localization::FloorObservations out;
  out.stamp_s = stamp_s;
  out.view = view_;
  std::normal_distribution<double> normal(0.0, 1.0);
  const core::SE2 T_base_map = T_map_base_true.Inverse();
  const double reach_m = options_.max_ahead_m + options_.half_width_m;
  const double s2 = options_.endpoint_sigma_m * options_.endpoint_sigma_m;
  for (const localization::MarkingSegment& segment : segments_) {
    const Eigen::Vector2d a = T_base_map * segment.a_m;
    const Eigen::Vector2d b = T_base_map * segment.b_m;
    // Cheap rejection: both ends far beyond the view on the same side.
    if ((a.x() > reach_m && b.x() > reach_m) || (a.x() < 0.0 && b.x() < 0.0)) continue;
    const auto clipped = Clip(a, b, options_.min_ahead_m, options_.max_ahead_m,
                              -options_.half_width_m, options_.half_width_m);
    if (!clipped || (clipped->second - clipped->first).norm() < options_.min_length_m) continue;
    Eigen::Matrix2d J1;
    Eigen::Matrix2d J2;
    const auto line = perception::LineFromPoints(clipped->first, clipped->second, &J1, &J2);
    if (!line.ok()) continue;
    localization::LineObservation observation;
    observation.covariance = s2 * (J1 * J1.transpose() + J2 * J2.transpose());
    const Eigen::Matrix2d L = observation.covariance.llt().matrixL();
    const Eigen::Vector2d noise = L * core::DrawVector<2>(normal, rng_);
    observation.line_base =
        perception::NormalizeLine(line->rho_m + noise(0), line->alpha_rad + noise(1));
    observation.kind = segment.kind;
    observation.endpoint_a_base_m = clipped->first;
    observation.endpoint_b_base_m = clipped->second;
    out.lines.push_back(observation);
  }
  for (const Eigen::Vector2d& junction : junctions_) {
    const Eigen::Vector2d p = T_base_map * junction;
    if (p.x() < options_.min_ahead_m || p.x() > options_.max_ahead_m ||
        std::abs(p.y()) > options_.half_width_m) {
      continue;
    }
    localization::JunctionObservation observation;
    const double sigma = options_.junction_sigma_m;
    observation.point_base_m = p + sigma * core::DrawVector<2>(normal, rng_);
    observation.covariance = Eigen::Matrix2d::Identity() * sigma * sigma;
    out.junctions.push_back(observation);
  }
  return out;
}

}  // namespace groundline::sim
