#include "groundline/localization/observations_from_extraction.h"

#include <Eigen/Cholesky>

namespace groundline::localization {
namespace {

bool IsSymmetricPositiveDefinite(const Eigen::Matrix2d& m) {
  if (!m.allFinite()) return false;
  if (std::abs(m(0, 1) - m(1, 0)) > 1e-9 * (std::abs(m(0, 0)) + std::abs(m(1, 1)))) return false;
  return Eigen::LLT<Eigen::Matrix2d>(m).info() == Eigen::Success;
}

core::MarkingKind KindOf(const perception::LineKind& kind) {
  if (kind.polarity == perception::LinePolarity::kDark) return core::MarkingKind::kJoint;
  if (kind.orientation == perception::LineOrientation::kTransverse) {
    return core::MarkingKind::kStopBar;
  }
  return core::MarkingKind::kTapeSolid;
}

}  // namespace

ConvertedObservations ObservationsFromExtraction(double stamp_s,
                                                 const perception::LineExtraction& extraction) {
  ConvertedObservations out;
  out.observations.stamp_s = stamp_s;
  for (const perception::ExtractedLine& line : extraction.lines) {
    if (line.single_bar_edge) {
      ++out.skipped_bar_edges;
      continue;
    }
    if (!IsSymmetricPositiveDefinite(line.covariance)) {
      ++out.dropped_lines;
      continue;
    }
    LineObservation observation;
    observation.line_base = line.line;
    observation.covariance = line.covariance;
    observation.kind = KindOf(line.kind);
    observation.endpoint_a_base_m = line.start_m;
    observation.endpoint_b_base_m = line.end_m;
    out.observations.lines.push_back(observation);
  }
  for (const perception::Junction& junction : extraction.junctions) {
    if (!IsSymmetricPositiveDefinite(junction.covariance)) {
      ++out.dropped_junctions;
      continue;
    }
    out.observations.junctions.push_back({junction.point_m, junction.covariance});
  }
  return out;
}

}  // namespace groundline::localization
