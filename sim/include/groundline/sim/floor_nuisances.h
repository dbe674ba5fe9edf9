// The floor renderer's straight nuisances as geometry, and the randomized
// nuisance preset.
//
// Some nuisances have straight edges that a line extractor may take for a
// marking: cast shadows of racks and pallets, the vehicle's own shadow, rows of
// glare under strip luminaires, tire marks along the lanes and the seams of
// patched concrete (floor_camera.h, FloorRenderOptions). The renderer draws
// them; the functions here list them, so that an evaluation can tell which
// nuisance a false line came from. They are ground truth of the simulator:
// only evaluation code may read them (`groundline sim` writes them beside the
// dataset's ground truth, in nuisance_truth.json).
#ifndef GROUNDLINE_SIM_FLOOR_NUISANCES_H_
#define GROUNDLINE_SIM_FLOOR_NUISANCES_H_

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/sim/floor_camera.h"

namespace groundline::sim {

enum class NuisanceClass {
  kCastShadowEdge,     // the edge of a rack's or pallet's shadow (map frame)
  kVehicleShadowEdge,  // the edge of the vehicle's own shadow (base_link, per frame)
  kGlareRow,           // the centre line of a row of glare spots (map frame)
  kTireMark,           // the centre line of a tire mark (map frame)
  kPatchSeam,          // the edge of a patch of repaired concrete (map frame)
};
inline constexpr int kNuisanceClassCount = 5;
// "cast_shadow_edge", "vehicle_shadow_edge", "glare_row", "tire_mark", "patch_seam".
std::string_view NuisanceClassName(NuisanceClass c);

struct NuisanceSegment {
  NuisanceClass cls = NuisanceClass::kCastShadowEdge;
  Vector2 a_m = Vector2::Zero();
  Vector2 b_m = Vector2::Zero();
};

// The straight nuisances fixed on the floor (every class but the vehicle's
// shadow) that lie, at least in part, in the box [lo_m, hi_m] of the map, for
// the renderer made with these options (the same seed gives the same floor).
// Empty when none of them is enabled.
std::vector<NuisanceSegment> FloorNuisanceSegments(const FloorRenderOptions& options,
                                                   const Vector2& lo_m, const Vector2& hi_m);

// The vehicle's own shadow at T_map_base: a convex polygon in base_link
// (counter-clockwise), the hull of the vehicle's footprint and its top face
// projected onto the floor from the nearest luminaire of the grid; nullopt
// when options.vehicle_shadow is off or the luminaires are not above the
// vehicle's top.
std::optional<std::vector<Vector2>> VehicleShadowPolygon(const FloorRenderOptions& options,
                                                         const core::SE2& T_map_base);

// A scene's nuisances drawn from wide ranges (every nuisance on; texture scale
// and contrast, lux and gradient, shadows, glare size, count and rows, tire
// marks, patches, wet areas, blur and noise each drawn per scene), seeded.
// The ranges are in floor_nuisances.cc and docs/perception.md.
FloorRenderOptions RandomizedRenderOptions(std::uint64_t seed);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_FLOOR_NUISANCES_H_
