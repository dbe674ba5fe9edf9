#include "groundline/localization/observations_from_extraction.h"

#include "groundline/core/covariance.h"

namespace groundline::localization {
namespace {

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
    if (!core::IsCovariance(line.covariance)) {
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
    if (!core::IsCovariance(junction.covariance)) {
      ++out.dropped_junctions;
      continue;
    }
    out.observations.junctions.push_back({junction.point_m, junction.covariance});
  }
  return out;
}

}  // namespace groundline::localization
