// The floor-marking map: the ground-truth markings of a site, as the
// simulator renders them and as line detections are evaluated against them
// (format: docs/dataset.md, "floor_map.yaml").
//
// Every marking is a polyline of its centre line in the map frame (metres),
// painted with a width. A closed outline repeats its first vertex at the end.
#ifndef GROUNDLINE_CORE_FLOOR_MAP_H_
#define GROUNDLINE_CORE_FLOOR_MAP_H_

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::core {

inline constexpr char kFloorMapFormatName[] = "groundline-floor-map";
inline constexpr int kFloorMapFormatMajor = 1;
inline constexpr int kFloorMapFormatMinor = 1;

enum class MarkingKind {
  kTapeSolid,        // continuous tape line (aisle edge, lane divider)
  kTapeDashed,       // dashed tape line; dash_m / gap_m set
  kStopBar,          // short transverse bar across a lane
  kCrosswalkStripe,  // one stripe of a pedestrian crossing (one marking per stripe)
  kStagingBoxEdge,   // outline of a floor staging area
  kJoint,            // saw-cut expansion joint in the concrete (a dark groove)
  // Not a floor marking: a straight vertical face (rack face, wall) seen by the
  // planar LiDAR. Atlas lines of this kind associate only with LiDAR wall
  // observations (floor_association.h); the simulator writes the faces of its
  // installation drawing into the dataset's floor map after the markings.
  kWall,
  // A rack face: the line of the upright fronts, with the loads set back a
  // few centimetres behind them, so that the LiDAR sees a recessed band and
  // takes the face from its front (lidar/wall_lines.h). A kWall is a solid
  // face (building wall, column, closed door) seen as one plain band.
  kRackFace,
};
// The file spelling: "tape_solid", "tape_dashed", "stop_bar",
// "crosswalk_stripe", "staging_box_edge", "joint", "wall", "rack_face".
std::string_view MarkingKindName(MarkingKind kind);
std::optional<MarkingKind> MarkingKindFromName(std::string_view name);
// kWall or kRackFace: a vertical face seen by the LiDAR, not a floor marking.
bool IsFaceKind(MarkingKind kind);

// Contrast against the floor: what a ridge detector looks for.
enum class MarkingPolarity { kBright, kDark };  // "bright" / "dark"

struct FloorMarking {
  std::int64_t id = 0;  // >= 0, unique within the map
  MarkingKind kind = MarkingKind::kTapeSolid;
  double width_m = 0.0;                       // > 0, across the centre line
  std::array<int, 3> colour_rgb = {0, 0, 0};  // 8-bit sRGB, for rendering
  MarkingPolarity polarity = MarkingPolarity::kBright;
  // Centre line in the map frame: >= 2 vertices, consecutive ones >= 1 mm apart.
  std::vector<Vector2> polyline_m;
  // Only for kTapeDashed (both > 0; absent otherwise): the pattern starts
  // with a full dash at the first vertex and runs along the polyline's arc length.
  std::optional<double> dash_m;
  std::optional<double> gap_m;
};

// Since 1.1, optional: the stated accuracy of the survey the map comes from
// (1 sigma, each > 0). A map without it states none, and its users assume
// their own defaults.
struct FloorMapSurvey {
  // Every vertex of a floor marking's polyline, along each axis, independent
  // from vertex to vertex (a tape or total-station survey).
  double marking_vertex_sigma_m = 0.003;
  // A wall or rack face as a whole (a layout drawing): a shift across it and
  // a turn about its midpoint.
  double face_offset_sigma_m = 0.02;
  double face_angle_sigma_rad = 0.0034906585039886592;  // 0.2 deg
};

struct FloorMap {
  std::string frame = "map";  // the frame of every polyline
  std::vector<FloorMarking> markings;
  std::optional<FloorMapSurvey> survey;

  // Checks the rules above (ids, widths, colours, polylines, dash pattern);
  // the message names the marking by id and index.
  Status Validate() const;
};

// Reads and validates floor_map.yaml. Errors name file, line and field
// ("floor_map.yaml:14: field 'markings[2].width_m': expected a number > 0, got '0'").
// A higher major version is rejected.
Result<FloorMap> ReadFloorMap(const std::filesystem::path& path);
// Validates, then writes atomically. Coordinates are written in the shortest
// form that reads back to the same double (exact round trip).
Status WriteFloorMap(const std::filesystem::path& path, const FloorMap& map);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_FLOOR_MAP_H_
