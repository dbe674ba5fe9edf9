// Simulated floor-line and junction observations for localization tests and
// benchmarks, drawn from the ground-truth floor map and the true pose instead
// of rendered images (no extractor in the loop: accuracy figures obtained
// with them measure the estimator, not the perception).
//
// The camera sees the floor in base_link over x in [min_ahead_m, max_ahead_m],
// |y| <= half_width_m. Each marking centre-line segment clipped to that box
// (at least min_length_m long) gives a LineObservation: the true line through
// the clipped endpoints plus Gaussian noise of the covariance the endpoints'
// noise implies, Sigma = s^2 (J1 J1^T + J2 J2^T) (perception::LineFromPoints),
// s = endpoint_sigma_m. Each junction of localization::MarkingJunctions in the
// box gives a JunctionObservation with isotropic noise junction_sigma_m.
// Dashed tape is treated as continuous (its gaps are not simulated). Every
// observation's view is that box.
//
// Deterministic for a seed; not thread-safe (one random engine).
#ifndef GROUNDLINE_SIM_FLOOR_LINE_OBSERVATIONS_H_
#define GROUNDLINE_SIM_FLOOR_LINE_OBSERVATIONS_H_

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "groundline/core/floor_map.h"
#include "groundline/core/se2.h"
#include "groundline/core/status.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_observation.h"

namespace groundline::sim {

struct FloorObservationOptions {
  double min_ahead_m = 0.6;
  double max_ahead_m = 2.4;
  double half_width_m = 1.0;
  double min_length_m = 0.3;
  double endpoint_sigma_m = 0.01;
  double junction_sigma_m = 0.015;
  std::uint64_t seed = 1;

  core::Status Validate() const;
};

class FloorObservationSimulator {
 public:
  // options must be valid (asserted).
  FloorObservationSimulator(const core::FloorMap& map, const FloorObservationOptions& options);

  localization::FloorObservations Observe(double stamp_s, const core::SE2& T_map_base_true);

 private:
  FloorObservationOptions options_;
  std::vector<localization::MarkingSegment> segments_;
  std::vector<Eigen::Vector2d> junctions_;
  std::shared_ptr<const localization::FloorView> view_;  // the box, on every observation
  std::mt19937_64 rng_;
};

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_FLOOR_LINE_OBSERVATIONS_H_
