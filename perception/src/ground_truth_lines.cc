// Visible map markings and line matching (ground_truth_lines.h).
#include "groundline/perception/ground_truth_lines.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace groundline::perception {

namespace {

// Accumulates the seen samples of one true line.
struct SeenLine {
  TrueLine line;
  bool any = false;

  double run_m = 0.0;                  // the current run of evaluated samples
  double last_evaluated_s_m = -1e300;  // arc length of the last evaluated sample

  // p: the sample at arc length s_m along the piece.
  void Add(const Eigen::Vector2d& p, double s_m, const VisibleLineOptions& options) {
    if (!any) line.start_m = p;
    line.end_m = p;
    any = true;
    line.seen_length_m += options.sample_step_m;
    if (p.x() >= options.eval_x_min_m && p.x() <= options.eval_x_max_m) {
      line.evaluated_length_m += options.sample_step_m;
      const bool next = s_m - last_evaluated_s_m <= 1.5 * options.sample_step_m;
      run_m = next ? run_m + options.sample_step_m : options.sample_step_m;
      last_evaluated_s_m = s_m;
      line.longest_evaluated_run_m = std::max(line.longest_evaluated_run_m, run_m);
    }
  }
  bool LongEnough(const VisibleLineOptions& options) const {
    return line.evaluated_length_m >= options.min_evaluated_length_m - 1e-9 &&
           line.longest_evaluated_run_m >= options.min_evaluated_run_m - 1e-9;
  }
};

// A straight piece of a bright marking as painted (one dash of a dashed
// tape), in base_link: the floor it covers.
struct Cover {
  Eigen::Vector2d a_m, dir;
  double length_m = 0.0, half_width_m = 0.0;

  bool Contains(const Eigen::Vector2d& p) const {
    const double along = dir.dot(p - a_m);
    const double across = std::abs(dir.x() * (p.y() - a_m.y()) - dir.y() * (p.x() - a_m.x()));
    return along >= 0.0 && along <= length_m && across <= half_width_m;
  }
};

// The painted pieces of the bright markings that reach within reach_m of
// base_link's origin.
std::vector<Cover> BrightCovers(const core::FloorMap& map, const core::SE2& T_base_map,
                                double reach_m) {
  std::vector<Cover> covers;
  for (const core::FloorMarking& marking : map.markings) {
    if (marking.polarity != core::MarkingPolarity::kBright) continue;
    const bool dashed =
        marking.kind == core::MarkingKind::kTapeDashed && marking.dash_m && marking.gap_m;
    const double period = dashed ? *marking.dash_m + *marking.gap_m : 0.0;
    double arc_m = 0.0;
    for (size_t k = 0; k + 1 < marking.polyline_m.size(); ++k) {
      const Eigen::Vector2d a = T_base_map * marking.polyline_m[k];
      const Eigen::Vector2d b = T_base_map * marking.polyline_m[k + 1];
      const double length = (b - a).norm();
      const Eigen::Vector2d dir = (b - a) / length;
      // Closest approach of the piece to the origin.
      const double t = std::clamp(-dir.dot(a), 0.0, length);
      if ((a + t * dir).norm() <= reach_m + 0.5 * marking.width_m) {
        if (!dashed) {
          covers.push_back({a, dir, length, 0.5 * marking.width_m});
        } else {
          for (double s = std::floor(arc_m / period) * period; s < arc_m + length; s += period) {
            const double d0 = std::max(s, arc_m) - arc_m;
            const double d1 = std::min(s + *marking.dash_m, arc_m + length) - arc_m;
            if (d1 > d0) covers.push_back({a + d0 * dir, dir, d1 - d0, 0.5 * marking.width_m});
          }
        }
      }
      arc_m += length;
    }
  }
  return covers;
}

}  // namespace

std::vector<TrueLine> VisibleMarkingLines(const core::FloorMap& map, const core::SE2& T_map_base,
                                          const FootprintPredicate& footprint,
                                          const VisibleLineOptions& options) {
  const core::SE2 T_base_map = T_map_base.Inverse();
  const std::vector<Cover> covers = options.tape_occludes_joints
                                        ? BrightCovers(map, T_base_map, options.occlusion_reach_m)
                                        : std::vector<Cover>{};
  auto occluded = [&](const Eigen::Vector2d& p) {
    return std::any_of(covers.begin(), covers.end(), [&](const Cover& c) { return c.Contains(p); });
  };
  std::vector<TrueLine> lines;
  for (const core::FloorMarking& marking : map.markings) {
    if (core::IsFaceKind(marking.kind)) continue;  // seen by the LiDAR, not on the floor
    const bool dashed =
        marking.kind == core::MarkingKind::kTapeDashed && marking.dash_m && marking.gap_m;
    const bool wide = marking.width_m >= options.edge_min_width_m;
    const bool coverable = marking.polarity == core::MarkingPolarity::kDark;
    const double half_width = 0.5 * marking.width_m;
    double arc_m = 0.0;  // arc length at the start of the piece
    for (size_t k = 0; k + 1 < marking.polyline_m.size(); ++k) {
      const Eigen::Vector2d a = T_base_map * marking.polyline_m[k];
      const Eigen::Vector2d b = T_base_map * marking.polyline_m[k + 1];
      const double length = (b - a).norm();
      const Eigen::Vector2d d = (b - a) / length;
      const Eigen::Vector2d left(-d.y(), d.x());
      // [0]: the centre line, [1]: the left edge, [2]: the right edge (wide only).
      SeenLine seen[3];
      for (double s = 0.0; s <= length; s += options.sample_step_m) {
        if (dashed && std::fmod(arc_m + s, *marking.dash_m + *marking.gap_m) > *marking.dash_m) {
          continue;
        }
        const Eigen::Vector2d p = a + s * d;
        if (!wide) {
          if (footprint(p) && !(coverable && occluded(p))) seen[0].Add(p, s, options);
          continue;
        }
        const Eigen::Vector2d pl = p + half_width * left, pr = p - half_width * left;
        const bool seen_left = footprint(pl), seen_right = footprint(pr);
        if (seen_left && seen_right) seen[0].Add(p, s, options);
        if (seen_left) seen[1].Add(pl, s, options);
        if (seen_right) seen[2].Add(pr, s, options);
      }
      arc_m += length;
      // Which one line the extractor reports (see the header).
      int reported = 0;
      if (wide) {
        const double longer = std::max(seen[1].line.seen_length_m, seen[2].line.seen_length_m);
        if (seen[0].line.seen_length_m < 0.5 * longer - 1e-9) {
          reported = seen[1].line.seen_length_m >= seen[2].line.seen_length_m ? 1 : 2;
          if (seen[reported].line.seen_length_m < options.edge_min_seen_length_m - 1e-9) {
            reported = -1;
          }
        }
      }
      for (int e = 0; e < 3; ++e) {
        if (!seen[e].any) continue;
        const double offset = e == 0 ? 0.0 : (e == 1 ? half_width : -half_width);
        core::Result<HesseLine> hesse = LineFromPoints(a + offset * left, b + offset * left);
        if (!hesse.ok()) continue;
        TrueLine line = seen[e].line;
        line.marking_id = marking.id;
        line.piece = static_cast<int>(k);
        line.kind = marking.kind;
        line.polarity = marking.polarity;
        line.edge = e == 0 ? 0 : (e == 1 ? 1 : -1);
        line.line = *hesse;
        line.evaluated = e == reported && seen[e].LongEnough(options);
        lines.push_back(line);
      }
    }
  }
  return lines;
}

namespace {

// Overlap of the extents of two segments along direction d.
double OverlapAlong(const Eigen::Vector2d& d, const Eigen::Vector2d& a0, const Eigen::Vector2d& a1,
                    const Eigen::Vector2d& b0, const Eigen::Vector2d& b1) {
  const double lo = std::max(std::min(d.dot(a0), d.dot(a1)), std::min(d.dot(b0), d.dot(b1)));
  const double hi = std::min(std::max(d.dot(a0), d.dot(a1)), std::max(d.dot(b0), d.dot(b1)));
  return hi - lo;
}

}  // namespace

LineMatches MatchLines(std::span<const LineSegmentEstimate> extracted,
                       std::span<const TrueLine> truths, const MatchGates& gates,
                       std::span<const core::MarkingPolarity> extracted_polarity) {
  assert(extracted_polarity.empty() || extracted_polarity.size() == extracted.size());
  LineMatches matches;
  matches.truth_of_extracted.assign(extracted.size(), -1);
  matches.extracted_of_truth.assign(truths.size(), -1);
  std::vector<double> cost_of_extracted(extracted.size(), 0.0);
  for (size_t i = 0; i < extracted.size(); ++i) {
    double best = 3.0;
    for (size_t j = 0; j < truths.size(); ++j) {
      if (!extracted_polarity.empty() && extracted_polarity[i] != truths[j].polarity) continue;
      const Eigen::Vector2d r = LineDifference(extracted[i].line, truths[j].line);
      if (std::abs(r(0)) > gates.rho_gate_m || std::abs(r(1)) > gates.alpha_gate_rad) continue;
      const Eigen::Vector2d d = truths[j].line.Direction();
      if (OverlapAlong(d, extracted[i].start_m, extracted[i].end_m, truths[j].start_m,
                       truths[j].end_m) < gates.min_overlap_m) {
        continue;
      }
      const double cost = std::abs(r(0)) / gates.rho_gate_m + std::abs(r(1)) / gates.alpha_gate_rad;
      if (cost < best) {
        best = cost;
        matches.truth_of_extracted[i] = static_cast<int>(j);
      }
    }
    cost_of_extracted[i] = best;
  }
  for (size_t i = 0; i < extracted.size(); ++i) {
    const int j = matches.truth_of_extracted[i];
    if (j < 0) continue;
    const int other = matches.extracted_of_truth[j];
    if (other < 0 || cost_of_extracted[i] < cost_of_extracted[other]) {
      matches.extracted_of_truth[j] = static_cast<int>(i);
    }
  }
  for (size_t i = 0; i < extracted.size(); ++i) {
    const int j = matches.truth_of_extracted[i];
    if (j >= 0 && matches.extracted_of_truth[j] != static_cast<int>(i)) {
      matches.truth_of_extracted[i] = -1;
    }
  }
  return matches;
}

}  // namespace groundline::perception
