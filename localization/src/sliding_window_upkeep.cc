// The atlas upkeep of SlidingWindowSmoother in localization mode
// (AtlasUpkeepOptions): each landmark's sightings record, and the retirement
// of landmarks that are expected in view and not seen.
#include "groundline/localization/sliding_window_smoother.h"

namespace groundline::localization {
namespace {

// A surveyed landmark has no record and gets none: a record says that the
// landmark was estimated from sightings (its covariance is that estimate's).
void RecordSighting(double stamp_s, std::optional<LandmarkSightings>* seen) {
  if (!seen->has_value()) return;
  LandmarkSightings& s = **seen;
  if (stamp_s > s.last_s) {
    ++s.keyframes;
    s.last_s = stamp_s;
  }
}

}  // namespace

void SlidingWindowSmoother::KeepAtlasCurrent(const FloorObservations& observations,
                                             const core::SE2& T_pred,
                                             const std::vector<bool>& lines_matched,
                                             const std::vector<bool>& junctions_matched,
                                             KeyframeHealth* health) {
  const AtlasUpkeepOptions& o = options_.upkeep;
  const double stamp_s = health->stamp_s;
  for (size_t i = 0; i < lines_matched.size(); ++i) {
    if (!lines_matched[i]) continue;
    line_misses_[i] = 0;
    RecordSighting(stamp_s, &atlas_.lines[i].seen);
  }
  for (size_t i = 0; i < junctions_matched.size(); ++i) {
    if (!junctions_matched[i]) continue;
    junction_misses_[i] = 0;
    RecordSighting(stamp_s, &atlas_.junctions[i].seen);
  }
  // A frame that matched nothing may not have been read (a dark or smeared
  // frame, a covered floor): it is no evidence against any landmark.
  if (observations.view == nullptr || health->lines_used + health->junctions_used == 0) return;
  const FloorView& view = *observations.view;
  const core::SE2 T_base_map = T_pred.Inverse();
  const auto retire = [&](std::vector<bool>* retired, size_t i) {
    (*retired)[i] = true;
    ++landmarks_retired_;
    ++health->landmarks_retired;
  };
  for (size_t i = 0; i < lines_matched.size(); ++i) {
    const AtlasLine& line = atlas_.lines[i];
    if (lines_matched[i] || line_retired_[i] || core::IsFaceKind(line.kind)) continue;
    if (view.LengthInside(T_base_map * line.endpoint_a_m, T_base_map * line.endpoint_b_m,
                          o.view_margin_m) < o.min_in_view_m) {
      continue;
    }
    if (++line_misses_[i] >= o.retire_after_misses) retire(&line_retired_, i);
  }
  for (size_t i = 0; i < junctions_matched.size(); ++i) {
    if (junctions_matched[i] || junction_retired_[i]) continue;
    const Eigen::Vector2d point(junction_blocks_[i][0], junction_blocks_[i][1]);
    if (view.InsideDistance(T_base_map * point) < o.view_margin_m) continue;
    if (++junction_misses_[i] >= o.retire_after_misses) retire(&junction_retired_, i);
  }
}

}  // namespace groundline::localization
