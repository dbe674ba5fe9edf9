#include "groundline/localization/atlas_walls.h"

#include <algorithm>
#include <string>

namespace groundline::localization {

core::Status AtlasWallOptions::Validate() const {
  if (!(rho_sigma_m > 0.0) || !(alpha_sigma_rad > 0.0)) {
    return core::Status::Error("AtlasWallOptions: rho_sigma_m and alpha_sigma_rad must be > 0");
  }
  return core::Status::Ok();
}

core::Status AppendWallLines(const std::vector<WallSegment>& segments,
                             const AtlasWallOptions& options, Atlas* atlas) {
  if (core::Status s = options.Validate(); !s.ok()) return s;
  std::int64_t next_id = 0;
  for (const AtlasLine& line : atlas->lines) {
    next_id = std::max(next_id, line.id + 1);
  }
  std::vector<AtlasLine> added;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const core::Result<perception::HesseLine> line =
        perception::LineFromPoints(segments[i].a_m, segments[i].b_m);
    if (!line.ok() || (segments[i].b_m - segments[i].a_m).norm() < 1e-3) {
      return core::Status::Error("wall segment " + std::to_string(i) +
                                 ": its end points are less than 1 mm apart");
    }
    AtlasLine wall;
    wall.id = next_id++;
    wall.line_map = *line;
    // About the face's midpoint, where the survey's shift and turn are
    // independent (LineCovarianceAbout), not about the map origin.
    wall.covariance = LineCovarianceAbout(*line, 0.5 * (segments[i].a_m + segments[i].b_m),
                                          options.rho_sigma_m, options.alpha_sigma_rad);
    wall.kind = segments[i].rack_face ? core::MarkingKind::kRackFace : core::MarkingKind::kWall;
    wall.endpoint_a_m = segments[i].a_m;
    wall.endpoint_b_m = segments[i].b_m;
    added.push_back(wall);
  }
  atlas->lines.insert(atlas->lines.end(), added.begin(), added.end());
  return core::Status::Ok();
}

int CountWallLines(const Atlas& atlas) {
  return static_cast<int>(
      std::count_if(atlas.lines.begin(), atlas.lines.end(),
                    [](const AtlasLine& l) { return core::IsFaceKind(l.kind); }));
}

}  // namespace groundline::localization
