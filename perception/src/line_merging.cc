// Side-lobe removal and the merging of lines of one marking (line_sides.h).
#include <algorithm>
#include <cmath>

#include "line_sides.h"

namespace groundline::perception::internal {

void DropSideLobes(double max_distance_m, double max_angle_rad, std::vector<ExtractedLine>* lines) {
  std::vector<bool> drop(lines->size(), false);
  for (size_t b = 0; b < lines->size(); ++b) {
    const ExtractedLine& bright = (*lines)[b];
    if (bright.kind.polarity != LinePolarity::kBright || bright.from_bar_edges ||
        bright.single_bar_edge) {
      continue;
    }
    for (const ExtractedLine& dark : *lines) {
      if (dark.kind.polarity != LinePolarity::kDark) continue;
      const Eigen::Vector2d r = LineDifference(bright.line, dark.line);
      if (std::abs(r(1)) > max_angle_rad) continue;
      const Eigen::Vector2d mid = 0.5 * (bright.start_m + bright.end_m);
      if (std::abs(SignedDistance(dark.line, mid)) > max_distance_m) continue;
      if (Overlap(bright, dark) < 0.5 * bright.LengthM()) continue;
      drop[b] = true;
      break;
    }
  }
  size_t kept = 0;
  for (size_t i = 0; i < lines->size(); ++i) {
    if (!drop[i]) (*lines)[kept++] = (*lines)[i];
  }
  lines->resize(kept);
}

void MergeSameMarkingLines(double max_distance_m, double max_angle_rad,
                           std::vector<ExtractedLine>* lines) {
  std::stable_sort(
      lines->begin(), lines->end(),
      [](const ExtractedLine& a, const ExtractedLine& b) { return a.samples > b.samples; });
  auto same_construction = [](const ExtractedLine& a, const ExtractedLine& b) {
    return a.kind.polarity == b.kind.polarity && a.from_bar_edges == b.from_bar_edges &&
           a.single_bar_edge == b.single_bar_edge;
  };
  // shorter lies inside longer's band: both its ends within max_distance_m of
  // longer's line, at most max_angle askew, overlapping it over min_overlap of
  // its length.
  auto in_band = [max_distance_m](const ExtractedLine& longer, const ExtractedLine& shorter,
                                  double max_angle, double min_overlap) {
    return std::abs(LineDifference(shorter.line, longer.line)(1)) <= max_angle &&
           std::abs(SignedDistance(longer.line, shorter.start_m)) <= max_distance_m &&
           std::abs(SignedDistance(longer.line, shorter.end_m)) <= max_distance_m &&
           Overlap(longer, shorter) >= min_overlap * shorter.LengthM();
  };
  std::vector<ExtractedLine> kept;
  std::vector<std::vector<const ExtractedLine*>> groups;
  for (const ExtractedLine& line : *lines) {
    int group = -1;
    bool pieces = false;
    for (size_t k = 0; k < kept.size() && group < 0; ++k) {
      if (!same_construction(kept[k], line)) continue;
      const Eigen::Vector2d r = LineDifference(line.line, kept[k].line);
      pieces = std::abs(r(0)) <= kDuplicateRhoM && std::abs(r(1)) <= kDuplicateAlphaRad;
      const ExtractedLine& longer = kept[k].LengthM() >= line.LengthM() ? kept[k] : line;
      const ExtractedLine& shorter = &longer == &line ? kept[k] : line;
      if (pieces || in_band(longer, shorter, max_angle_rad, 0.5)) group = static_cast<int>(k);
    }
    // A line at most half as long as a kept one, inside its band at up to 3x
    // max_angle_rad, is a piece of that marking pulled askew (where a bar's
    // corner meets a tape, the tape's ridge bends toward the corner for a few
    // decimetres): dropped, not averaged in, which would tilt the marking's line.
    if (group < 0 && std::any_of(kept.begin(), kept.end(), [&](const ExtractedLine& k) {
          return same_construction(k, line) && line.LengthM() <= 0.5 * k.LengthM() &&
                 in_band(k, line, 3.0 * max_angle_rad, 0.8);
        })) {
      continue;
    }
    if (group < 0) {
      kept.push_back(line);
      groups.push_back({&line});
    } else if (pieces) {
      // The same ridge (its centres sampled twice): the first spans both.
      const ExtractedLine keep = kept[group];
      SpanEndpoints(keep, line, &kept[group]);
    } else {
      groups[group].push_back(&line);
    }
  }
  for (size_t k = 0; k < kept.size(); ++k) {
    if (groups[k].size() == 1) continue;
    groups[k].front() = &kept[k];  // with the span of its pieces
    // Samples-weighted mean about the first (most samples) line.
    const ExtractedLine& first = *groups[k].front();
    double total = 0.0;
    Eigen::Vector2d mean_difference = Eigen::Vector2d::Zero();
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
    for (const ExtractedLine* member : groups[k]) total += member->samples;
    ExtractedLine merged = first;
    for (const ExtractedLine* member : groups[k]) {
      const double w = member->samples / total;
      mean_difference += w * LineDifference(member->line, first.line);
      covariance += w * CovarianceInDescriptionOf(member->line, first.line, member->covariance);
      SpanEndpoints(merged, *member, &merged);
    }
    merged.line = NormalizeLine(first.line.rho_m + mean_difference(0),
                                first.line.alpha_rad + mean_difference(1), &covariance);
    merged.covariance = covariance;
    merged.samples = static_cast<int>(total);
    SpanEndpoints(merged, merged, &merged);
    kept[k] = merged;
  }
  *lines = std::move(kept);
}

}  // namespace groundline::perception::internal
