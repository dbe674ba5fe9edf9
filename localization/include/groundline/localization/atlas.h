// The semantic atlas: the map of floor-marking landmarks the localizer
// matches against. Lines (Hesse normal form in the map frame, with their
// 2x2 covariance, marking kind and the extent seen so far) and junctions
// (points where markings meet or turn). Built by mapping mode from a drive
// or from a surveyed floor map (AtlasFromFloorMap); saved as JSON
// (docs/atlas.md).
//
// Lines are stored normalized (perception::NormalizeLine); their covariance
// is of (rho_m, alpha_rad) in that description. Ids are unique per kind.
#ifndef GROUNDLINE_LOCALIZATION_ATLAS_H_
#define GROUNDLINE_LOCALIZATION_ATLAS_H_

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "groundline/core/floor_map.h"
#include "groundline/core/status.h"
#include "groundline/perception/hesse_line.h"

namespace groundline::localization {

inline constexpr char kAtlasFormatName[] = "groundline-atlas";
inline constexpr int kAtlasFormatMajor = 1;

// When and how often a landmark was seen (a mapping drive's keyframes that
// saw it), for keeping the atlas current: what has not been seen for long
// where it should have been can be retired.
struct LandmarkSightings {
  int keyframes = 0;  // distinct keyframes that saw it, >= 1
  double first_s = 0.0;
  double last_s = 0.0;  // >= first_s
};

struct AtlasLine {
  std::int64_t id = 0;
  perception::HesseLine line_map;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  // (rho_m, alpha_rad)
  core::MarkingKind kind = core::MarkingKind::kTapeSolid;
  // The marked extent along the line (metres, map frame).
  Eigen::Vector2d endpoint_a_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d endpoint_b_m = Eigen::Vector2d::Zero();
  // Absent for a surveyed landmark. Present: the landmark was estimated from
  // the sightings of a drive (AtlasMapper, or born by the localizer's atlas
  // upkeep), and a localizing smoother weighs its covariance as stated even
  // when covariances_stated is false.
  std::optional<LandmarkSightings> seen;
  // The atlas upkeep's evidence that the landmark is gone: the keyframes in a
  // row, over the drives that kept this atlas, in which it was expected in
  // the camera's view and not seen (SmootherOptions::upkeep). Stored as
  // `missed` (absent: 0).
  int missed = 0;
};

struct AtlasJunction {
  std::int64_t id = 0;
  Eigen::Vector2d point_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
  std::optional<LandmarkSightings> seen;
  int missed = 0;  // as AtlasLine::missed
};

struct Atlas {
  std::string frame = "map";
  std::vector<AtlasLine> lines;
  std::vector<AtlasJunction> junctions;
  // Whether the covariances are the landmarks' accuracy as stated by a
  // survey (AtlasFromFloorMap of a floor map with a survey block) or by the
  // joint solve of a mapping drive (AtlasMapper: each landmark's marginal).
  // A localizing smoother weighs its line and junction factors by such
  // covariances (SmootherOptions::landmark_covariance_in_factors).
  // Otherwise (the assumed accuracy of a map that states none, the causal
  // mapping smoother's landmarks) they only widen the association gate.
  // Stored in the atlas file as `covariances_stated` (absent: false).
  bool covariances_stated = false;

  // Finite values, normalized lines, symmetric positive definite
  // covariances, unique ids; the message names the entry ("lines[3].covariance").
  core::Status Validate() const;
};

// Reads and validates an atlas file. Errors name the file and the field
// ("atlas.json: field 'lines[2].rho_m': expected a number, got \"x\"").
core::Result<Atlas> ReadAtlas(const std::filesystem::path& path);
// Validates, then writes atomically (FILE.tmp, then rename).
core::Status WriteAtlas(const std::filesystem::path& path, const Atlas& atlas);

// The (rho_m, alpha_rad) covariance of `line` (map-origin Hesse description)
// whose errors are independent at `anchor_m`, a point on the line (a marked
// segment's midpoint): a shift of sigma_m along the normal there and a turn of
// sigma_rad about it. Turning the line about the anchor moves its origin
// distance by (Direction . anchor) dalpha, so
//   Sigma = J diag(sigma_m^2, sigma_rad^2) J^T,  J = [1, Direction . anchor; 0, 1].
// An uncorrelated diag(sigma_m^2, sigma_rad^2) would instead turn the line
// about the foot of the map origin's perpendicular, tens of metres away in a
// large hall: sigma_rad = 2 mrad at 80 m is 16 cm of rho at the vehicle,
// which opened the association gate to the wrong edge of a crosswalk stripe.
Eigen::Matrix2d LineCovarianceAbout(const perception::HesseLine& line,
                                    const Eigen::Vector2d& anchor_m, double sigma_m,
                                    double sigma_rad);

// The survey accuracies assumed for a floor map that states none; a map with a
// survey block (core::FloorMapSurvey) is taken at its word instead.
struct AtlasFromFloorMapOptions {
  // Survey accuracy of a marking line, at the midpoint of each segment
  // (LineCovarianceAbout): across the line and its direction.
  double line_rho_sigma_m = 0.005;
  double line_alpha_sigma_rad = 0.002;
  double junction_sigma_m = 0.01;
  // A polyline vertex that turns by at least this much is a junction (a corner).
  double min_corner_angle_rad = 30.0 * std::numbers::pi / 180.0;
  // Junctions closer than this are merged.
  double junction_merge_distance_m = 0.05;
  // Survey accuracy of a wall or rack face (AtlasWallOptions, atlas_walls.h).
  double face_rho_sigma_m = 0.005;
  double face_alpha_sigma_rad = 0.002;

  core::Status Validate() const;
};

// A surveyed atlas from a floor map: one line per centre-line segment of
// every floor marking (dashed tape as its full segments), junctions at
// polyline corners and where segments of different floor markings cross or
// meet (a segment end within junction_merge_distance_m of another segment);
// then the map's wall and rack faces as face lines (AppendWallLines), which
// make no junctions. With the map's survey block, a segment's covariance
// follows from its vertices' sigma and its length, a junction's is the
// vertices' sigma, and a face's is the survey's face sigmas.
Atlas AtlasFromFloorMap(const core::FloorMap& map, const AtlasFromFloorMapOptions& options);

// The centre-line segments of the map's floor markings (no faces) with their
// kinds, and the junction points, as AtlasFromFloorMap finds them (shared
// with the observation simulator).
struct MarkingSegment {
  Eigen::Vector2d a_m;
  Eigen::Vector2d b_m;
  core::MarkingKind kind = core::MarkingKind::kTapeSolid;
};
std::vector<MarkingSegment> MarkingSegments(const core::FloorMap& map);
std::vector<Eigen::Vector2d> MarkingJunctions(const core::FloorMap& map,
                                              const AtlasFromFloorMapOptions& options);

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_ATLAS_H_
