#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "groundline/core/segment_distance.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/atlas_walls.h"

namespace groundline::localization {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

double DistanceToSegment(const Eigen::Vector2d& p, const MarkingSegment& s) {
  return core::DistanceToSegment(p, s.a_m, s.b_m);
}

void AddJunction(const Eigen::Vector2d& p, double merge_m, std::vector<Eigen::Vector2d>* out) {
  for (const Eigen::Vector2d& q : *out) {
    if ((q - p).norm() < merge_m) return;
  }
  out->push_back(p);
}

}  // namespace

Eigen::Matrix2d LineCovarianceAbout(const perception::HesseLine& line,
                                    const Eigen::Vector2d& anchor_m, double sigma_m,
                                    double sigma_rad) {
  Eigen::Matrix2d J;
  J << 1.0, line.Direction().dot(anchor_m), 0.0, 1.0;
  return J * Eigen::Vector2d(sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal() * J.transpose();
}

core::Status AtlasFromFloorMapOptions::Validate() const {
  if (!(line_rho_sigma_m > 0.0)) return core::Status::Error("line_rho_sigma_m must be > 0");
  if (!(line_alpha_sigma_rad > 0.0)) return core::Status::Error("line_alpha_sigma_rad must be > 0");
  if (!(junction_sigma_m > 0.0)) return core::Status::Error("junction_sigma_m must be > 0");
  if (!(min_corner_angle_rad > 0.0)) return core::Status::Error("min_corner_angle_rad must be > 0");
  if (!(junction_merge_distance_m >= 0.0)) {
    return core::Status::Error("junction_merge_distance_m must be >= 0");
  }
  if (!(face_rho_sigma_m > 0.0) || !(face_alpha_sigma_rad > 0.0)) {
    return core::Status::Error("face_rho_sigma_m and face_alpha_sigma_rad must be > 0");
  }
  return core::Status::Ok();
}

std::vector<MarkingSegment> MarkingSegments(const core::FloorMap& map) {
  std::vector<MarkingSegment> segments;
  for (const core::FloorMarking& marking : map.markings) {
    if (core::IsFaceKind(marking.kind)) continue;
    for (size_t i = 0; i + 1 < marking.polyline_m.size(); ++i) {
      segments.push_back({marking.polyline_m[i], marking.polyline_m[i + 1], marking.kind});
    }
  }
  return segments;
}

std::vector<Eigen::Vector2d> MarkingJunctions(const core::FloorMap& map,
                                              const AtlasFromFloorMapOptions& options) {
  std::vector<Eigen::Vector2d> junctions;
  const double merge_m = options.junction_merge_distance_m;
  for (const core::FloorMarking& marking : map.markings) {
    if (core::IsFaceKind(marking.kind)) continue;
    const auto& p = marking.polyline_m;
    const bool closed = p.size() > 3 && (p.front() - p.back()).norm() < 1e-9;
    for (size_t i = 0; i < p.size(); ++i) {
      const bool interior = i > 0 && i + 1 < p.size();
      if (!interior && !(closed && i == 0)) continue;
      const Eigen::Vector2d prev = i > 0 ? p[i - 1] : p[p.size() - 2];
      const Eigen::Vector2d next = p[i + 1];
      const Eigen::Vector2d d1 = (p[i] - prev).normalized();
      const Eigen::Vector2d d2 = (next - p[i]).normalized();
      if (std::abs(std::atan2(Cross(d1, d2), d1.dot(d2))) >= options.min_corner_angle_rad) {
        AddJunction(p[i], merge_m, &junctions);
      }
    }
  }
  // Crossings and T meetings between segments of different markings.
  std::vector<std::pair<MarkingSegment, size_t>> segments;
  for (size_t m = 0; m < map.markings.size(); ++m) {
    if (core::IsFaceKind(map.markings[m].kind)) continue;
    const auto& p = map.markings[m].polyline_m;
    for (size_t i = 0; i + 1 < p.size(); ++i) segments.push_back({{p[i], p[i + 1]}, m});
  }
  for (size_t i = 0; i < segments.size(); ++i) {
    for (size_t j = i + 1; j < segments.size(); ++j) {
      if (segments[i].second == segments[j].second) continue;
      const MarkingSegment& s = segments[i].first;
      const MarkingSegment& t = segments[j].first;
      const Eigen::Vector2d r = s.b_m - s.a_m;
      const Eigen::Vector2d q = t.b_m - t.a_m;
      const double denominator = Cross(r, q);
      if (std::abs(denominator) < 1e-9 * r.norm() * q.norm()) continue;  // parallel
      const double u = Cross(t.a_m - s.a_m, q) / denominator;
      const Eigen::Vector2d x = s.a_m + u * r;
      const bool on_s = DistanceToSegment(x, s) <= merge_m;
      const bool on_t = DistanceToSegment(x, t) <= merge_m;
      if (on_s && on_t) AddJunction(x, merge_m, &junctions);
    }
  }
  return junctions;
}

Atlas AtlasFromFloorMap(const core::FloorMap& map, const AtlasFromFloorMapOptions& options) {
  // The accuracy the map states, or else the options' assumptions.
  const core::FloorMapSurvey* survey = map.survey ? &*map.survey : nullptr;
  Atlas atlas;
  atlas.frame = map.frame;
  atlas.covariances_stated = survey != nullptr;
  for (const MarkingSegment& segment : MarkingSegments(map)) {
    const core::Result<perception::HesseLine> line =
        perception::LineFromPoints(segment.a_m, segment.b_m);
    if (!line.ok()) continue;
    AtlasLine entry;
    entry.id = static_cast<std::int64_t>(atlas.lines.size());
    entry.line_map = *line;
    double rho_sigma_m = options.line_rho_sigma_m;
    double alpha_sigma_rad = options.line_alpha_sigma_rad;
    if (survey) {
      // Two ends off by sigma each across the line, independently: the
      // midpoint moves by sigma / sqrt(2), the direction by sqrt(2) sigma / L,
      // and the two are uncorrelated.
      const double sigma = survey->marking_vertex_sigma_m;
      rho_sigma_m = sigma / std::numbers::sqrt2;
      alpha_sigma_rad = std::numbers::sqrt2 * sigma / (segment.b_m - segment.a_m).norm();
    }
    entry.covariance =
        LineCovarianceAbout(*line, 0.5 * (segment.a_m + segment.b_m), rho_sigma_m, alpha_sigma_rad);
    entry.kind = segment.kind;
    entry.endpoint_a_m = segment.a_m;
    entry.endpoint_b_m = segment.b_m;
    atlas.lines.push_back(entry);
  }
  const double junction_sigma_m =
      survey ? survey->marking_vertex_sigma_m : options.junction_sigma_m;
  const double variance = junction_sigma_m * junction_sigma_m;
  for (const Eigen::Vector2d& point : MarkingJunctions(map, options)) {
    atlas.junctions.push_back({static_cast<std::int64_t>(atlas.junctions.size()), point,
                               Eigen::Matrix2d::Identity() * variance, std::nullopt});
  }
  std::vector<WallSegment> faces;
  for (const core::FloorMarking& marking : map.markings) {
    if (!core::IsFaceKind(marking.kind)) continue;
    for (size_t i = 0; i + 1 < marking.polyline_m.size(); ++i) {
      faces.push_back({marking.polyline_m[i], marking.polyline_m[i + 1],
                       marking.kind == core::MarkingKind::kRackFace});
    }
  }
  AtlasWallOptions face_options;
  face_options.rho_sigma_m = survey ? survey->face_offset_sigma_m : options.face_rho_sigma_m;
  face_options.alpha_sigma_rad =
      survey ? survey->face_angle_sigma_rad : options.face_alpha_sigma_rad;
  // A validated floor map has no segment under 1 mm, so this cannot fail.
  [[maybe_unused]] const core::Status added = AppendWallLines(faces, face_options, &atlas);
  assert(added.ok());
  return atlas;
}

}  // namespace groundline::localization
