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
#include "groundline/core/trajectory.h"
#include "groundline/sim/floor_camera.h"

namespace groundline::sim {

enum class NuisanceClass {
  kCastShadowEdge,     // the edge of a rack's or pallet's shadow (map frame)
  kVehicleShadowEdge,  // the edge of the vehicle's own shadow (base_link, per frame)
  kGlareRow,           // the centre line of a row of glare spots (map frame)
  kTireMark,           // the centre line of a tire mark (map frame)
  kPatchSeam,          // the edge of a patch of repaired concrete (map frame)
  kStandingObject,     // the floor image of an object's edge (base_link, per frame)
};
inline constexpr int kNuisanceClassCount = 6;
// "cast_shadow_edge", "vehicle_shadow_edge", "glare_row", "tire_mark", "patch_seam",
// "standing_object".
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

// The simulator draws the static obstacles within this of the vehicle (the
// camera sees a few metres ahead; tall ones far to the side still matter).
inline constexpr double kStandingObjectRadiusM = 10.0;

// The world's static obstacles whose footprint comes within radius_m of
// near_m, as occluders with a camera reflectance per kind (steel uprights
// darker than pallets and walls), varied per obstacle.
std::vector<Occluder> StandingOccluders(const World& world, const Vector2& near_m, double radius_m);

// Where the camera at camera_map (map frame, above the floor) sees the edges
// of the occluders on the floor, in base_link (T_map_base): the footprint's
// edges, each vertical edge as the segment from its foot to the floor point
// seen through its top (along the ray from the camera's foot point; clipped
// at reach_m from it, and unbounded there when the top is at or above the
// camera), and each top edge below the camera projected onto the floor.
std::vector<NuisanceSegment> StandingObjectSegments(const std::vector<Occluder>& occluders,
                                                    const Eigen::Vector3d& camera_map,
                                                    const core::SE2& T_map_base,
                                                    double reach_m = 8.0);

// Adds clutter to world->obstacles beside the route (kPallet obstacles:
// pallets, boxes and posts), per_100m per 100 m of route on average, seeded.
// None overlaps the vehicle (vehicle_front_m, vehicle_back_m,
// vehicle_half_width_m of `vehicle`, plus a margin) at any pose of the route
// or comes within 0.1 m of a marking. Returns the number added.
int AddRouteClutter(World* world, const core::Trajectory& route, double per_100m,
                    const FloorRenderOptions& vehicle, std::uint64_t seed);

// A scene's nuisances drawn from wide ranges (every nuisance on; texture scale
// and contrast, lux and gradient, shadows, glare size, count and rows, tire
// marks, patches, wet areas, blur and noise each drawn per scene), seeded.
// The ranges are in floor_nuisances.cc and docs/perception.md.
FloorRenderOptions RandomizedRenderOptions(std::uint64_t seed);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_FLOOR_NUISANCES_H_
