// Ground-truth region labels of the zone presets (zones.h), for scoring the
// LiDAR degeneracy detector (match_information.h): is a map point deep in a
// LiDAR-degenerate corridor or in open space?
//
// - B: kAisle inside an aisle (between the facing rack faces, the rack run in
//   y) and more than end_margin_m from both aisle ends; kAisleEnd in the rest
//   of an aisle; kCrossAisle elsewhere (the cross-aisles at both ends). Only
//   where the aisle's end ahead is beyond the scanner's range (25 m for the
//   simulated TiM571, more than the 5 m margin the localizer's report uses)
//   does the scan see nothing but the periodic rack faces.
// - D: kCorridor inside one of the two long corridors, more than end_margin_m
//   from the end walls and from the side of every cross-corridor opening;
//   kJunction elsewhere (cross corridors, their openings, the ends).
// - A, C: kOpen everywhere.
//
// The geometry is that of the options given (the presets: default options;
// the seed changes only what stands in the racks and lanes, not the layout).
// Pure functions; thread-safe.
#ifndef GROUNDLINE_SIM_ZONE_REGIONS_H_
#define GROUNDLINE_SIM_ZONE_REGIONS_H_

#include "groundline/core/se2.h"
#include "groundline/sim/zones.h"

namespace groundline::sim {

enum class ZoneRegion { kOpen, kAisle, kAisleEnd, kCrossAisle, kCorridor, kJunction };

// "open", "aisle", "aisle_end", "cross_aisle", "corridor", "junction".
const char* ZoneRegionName(ZoneRegion region);
// True for the regions where a planar scan is expected to be degenerate
// (kAisle, kCorridor); false for kOpen, kCrossAisle and kJunction; kAisleEnd
// is neither (a transition, not scored).
bool IsCorridorRegion(ZoneRegion region);

ZoneRegion ZoneBRegionAt(const ZoneBOptions& options, const core::Vector2& p_map_m,
                         double end_margin_m);
ZoneRegion ZoneDRegionAt(const ZoneDOptions& options, const core::Vector2& p_map_m,
                         double end_margin_m);
// The region in a preset built with default options (BuildZone).
ZoneRegion PresetRegionAt(Zone zone, const core::Vector2& p_map_m, double end_margin_m);

}  // namespace groundline::sim

#endif  // GROUNDLINE_SIM_ZONE_REGIONS_H_
