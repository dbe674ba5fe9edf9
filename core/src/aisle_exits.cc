#include "groundline/core/aisle_exits.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "groundline/core/trajectory_association.h"

namespace groundline::core {
namespace {

struct Segment {
  Vector2 a_m;
  Vector2 b_m;
  double Length() const { return (b_m - a_m).norm(); }
  Vector2 Direction() const { return (b_m - a_m) / Length(); }
};

// The aisle between two straight tapes, if they qualify.
std::optional<Aisle> AisleBetween(const Segment& s, const Segment& t,
                                  const AisleExitOptions& options) {
  const Vector2 u = s.Direction();
  const double cross = u.x() * t.Direction().y() - u.y() * t.Direction().x();
  if (std::abs(cross) > std::sin(options.max_angle_rad)) return std::nullopt;
  const Vector2 n(-u.y(), u.x());
  const double width = n.dot(t.a_m - s.a_m);
  if (std::abs(width) < options.min_width_m || std::abs(width) > options.max_width_m) {
    return std::nullopt;
  }
  const double s0 = 0.0, s1 = s.Length();
  const double t0 = u.dot(t.a_m - s.a_m), t1 = u.dot(t.b_m - s.a_m);
  const double lo = std::max(s0, std::min(t0, t1));
  const double hi = std::min(s1, std::max(t0, t1));
  const double shorter = std::min(s.Length(), t.Length());
  if (hi - lo < options.min_overlap_share * shorter) return std::nullopt;
  const Vector2 centre_offset = 0.5 * width * n;
  return Aisle{s.a_m + lo * u + centre_offset, s.a_m + hi * u + centre_offset,
               0.5 * std::abs(width)};
}

// True if aisle `inner` lies between the tapes of `outer` (a wider pair that
// spans a narrower one: not an aisle of its own).
bool Spans(const Aisle& outer, const Aisle& inner) {
  return outer.half_width_m > inner.half_width_m &&
         outer.Contains(0.5 * (inner.start_m + inner.end_m));
}

}  // namespace

Status AisleExitOptions::Validate() const {
  if (!(min_length_m > 0.0)) return Status::Error("aisle min_length_m must be > 0");
  if (!(min_width_m > 0.0 && max_width_m > min_width_m)) {
    return Status::Error("aisle widths must satisfy 0 < min_width_m < max_width_m");
  }
  if (!(max_angle_rad >= 0.0)) return Status::Error("aisle max_angle_rad must be >= 0");
  if (!(min_overlap_share > 0.0 && min_overlap_share <= 1.0)) {
    return Status::Error("aisle min_overlap_share must be in (0, 1]");
  }
  if (!(min_inside_m >= 0.0)) return Status::Error("aisle min_inside_m must be >= 0");
  if (!(max_gap_s > 0.0)) return Status::Error("aisle max_gap_s must be > 0");
  if (!(error_threshold_m > 0.0)) return Status::Error("aisle error_threshold_m must be > 0");
  return Status::Ok();
}

bool Aisle::Contains(const Vector2& p_m) const {
  const Vector2 axis = end_m - start_m;
  const double length = axis.norm();
  const Vector2 u = axis / length;
  const double along = u.dot(p_m - start_m);
  const double across = u.x() * (p_m - start_m).y() - u.y() * (p_m - start_m).x();
  return along >= 0.0 && along <= length && std::abs(across) <= half_width_m;
}

std::vector<Aisle> FindAisles(const FloorMap& map, const AisleExitOptions& options) {
  std::vector<Segment> tapes;
  for (const FloorMarking& m : map.markings) {
    if (m.kind != MarkingKind::kTapeSolid || m.polyline_m.size() != 2) continue;
    const Segment s{m.polyline_m[0], m.polyline_m[1]};
    if (s.Length() >= options.min_length_m) tapes.push_back(s);
  }
  std::vector<Aisle> candidates;
  for (std::size_t i = 0; i < tapes.size(); ++i) {
    for (std::size_t j = i + 1; j < tapes.size(); ++j) {
      if (std::optional<Aisle> aisle = AisleBetween(tapes[i], tapes[j], options)) {
        candidates.push_back(*aisle);
      }
    }
  }
  std::vector<Aisle> aisles;
  for (const Aisle& a : candidates) {
    const bool spans_another = std::any_of(candidates.begin(), candidates.end(),
                                           [&](const Aisle& b) { return Spans(a, b); });
    if (!spans_another) aisles.push_back(a);
  }
  return aisles;
}

std::vector<AisleExit> FindAisleExits(const Trajectory& reference, const std::vector<Aisle>& aisles,
                                      const AisleExitOptions& options) {
  std::vector<AisleExit> exits;
  for (std::size_t k = 0; k < aisles.size(); ++k) {
    double inside_m = 0.0;
    bool inside = false;
    for (std::size_t i = 0; i < reference.size(); ++i) {
      const Vector2 p = reference[i].pose.translation();
      const bool now_inside = aisles[k].Contains(p);
      if (now_inside && inside) inside_m += (p - reference[i - 1].pose.translation()).norm();
      if (!now_inside && inside && inside_m >= options.min_inside_m) {
        exits.push_back({reference[i].stamp_s, k});
      }
      if (!now_inside) inside_m = 0.0;
      inside = now_inside;
    }
  }
  std::sort(exits.begin(), exits.end(),
            [](const AisleExit& a, const AisleExit& b) { return a.stamp_s < b.stamp_s; });
  return exits;
}

Result<AisleExitSummary> ComputeAisleExitErrors(const Trajectory& estimate,
                                                const Trajectory& reference, const FloorMap& map,
                                                const AisleExitOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  if (estimate.empty() || reference.empty()) {
    return Status::Error("aisle exits: empty estimate or reference trajectory");
  }
  AisleExitSummary summary;
  const std::vector<AisleExit> exits = FindAisleExits(reference, FindAisles(map, options), options);
  summary.n_exits = exits.size();
  if (exits.empty()) return summary;
  // The true poses at the exits, matched to the estimate interpolated there.
  Trajectory at_exits;
  for (const AisleExit& exit : exits) {
    const auto it = std::lower_bound(reference.begin(), reference.end(), exit.stamp_s,
                                     [](const StampedPose& p, double t) { return p.stamp_s < t; });
    if (!at_exits.empty() && !(it->stamp_s > at_exits.back().stamp_s)) continue;
    at_exits.push_back({it->stamp_s, it->pose, std::nullopt});
  }
  AssociationOptions association;
  association.method = AssociationMethod::kInterpolate;
  association.max_dt_s = 1e-6;
  association.max_interpolation_gap_s = options.max_gap_s;
  std::vector<double> errors;
  Result<Association> matched = AssociateByStamp(at_exits, estimate, association);
  if (matched.ok()) {
    for (const PosePair& pair : matched->pairs) {
      // pair.T_map_est is the true exit pose, pair.T_map_ref the estimate there.
      errors.push_back((pair.T_map_ref.translation() - pair.T_map_est.translation()).norm());
    }
  }
  summary.n_unmatched = summary.n_exits - errors.size();
  summary.n_above_threshold = static_cast<std::size_t>(std::count_if(
      errors.begin(), errors.end(), [&](double e) { return e > options.error_threshold_m; }));
  summary.error_m = ComputeErrorStats(std::move(errors));
  return summary;
}

}  // namespace groundline::core
