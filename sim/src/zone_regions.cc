#include "groundline/sim/zone_regions.h"

#include <cmath>

namespace groundline::sim {

const char* ZoneRegionName(ZoneRegion region) {
  switch (region) {
    case ZoneRegion::kOpen:
      return "open";
    case ZoneRegion::kAisle:
      return "aisle";
    case ZoneRegion::kAisleEnd:
      return "aisle_end";
    case ZoneRegion::kCrossAisle:
      return "cross_aisle";
    case ZoneRegion::kCorridor:
      return "corridor";
    case ZoneRegion::kJunction:
      return "junction";
  }
  return "open";
}

bool IsCorridorRegion(ZoneRegion region) {
  return region == ZoneRegion::kAisle || region == ZoneRegion::kCorridor;
}

ZoneRegion ZoneBRegionAt(const ZoneBOptions& o, const core::Vector2& p, double end_margin_m) {
  const double y0 = o.RackStartYM();
  const double y1 = y0 + o.aisle_length_m;
  if (p.y() < y0 || p.y() > y1) return ZoneRegion::kCrossAisle;
  const double half_w = 0.5 * o.aisle_clear_width_m;
  for (int i = 0; i < o.num_aisles; ++i) {
    if (std::abs(p.x() - o.AisleCenterXM(i)) > half_w) continue;
    const bool deep = p.y() > y0 + end_margin_m && p.y() < y1 - end_margin_m;
    return deep ? ZoneRegion::kAisle : ZoneRegion::kAisleEnd;
  }
  return ZoneRegion::kCrossAisle;  // inside a rack footprint: not a driving region
}

ZoneRegion ZoneDRegionAt(const ZoneDOptions& o, const core::Vector2& p, double end_margin_m) {
  const double w = o.corridor_width_m;
  const bool south = p.y() >= 0.0 && p.y() <= w;
  const bool north = p.y() >= o.corridor_separation_m && p.y() <= o.corridor_separation_m + w;
  if (!south && !north) return ZoneRegion::kJunction;
  if (p.x() < end_margin_m || p.x() > o.corridor_length_m - end_margin_m) {
    return ZoneRegion::kJunction;
  }
  for (int k = 0; k < o.num_cross_corridors; ++k) {
    if (std::abs(p.x() - o.CrossCorridorCenterXM(k)) < 0.5 * w + end_margin_m) {
      return ZoneRegion::kJunction;
    }
  }
  return ZoneRegion::kCorridor;
}

ZoneRegion PresetRegionAt(Zone zone, const core::Vector2& p_map_m, double end_margin_m) {
  switch (zone) {
    case Zone::kB:
      return ZoneBRegionAt(ZoneBOptions(), p_map_m, end_margin_m);
    case Zone::kD:
      return ZoneDRegionAt(ZoneDOptions(), p_map_m, end_margin_m);
    case Zone::kA:
    case Zone::kC:
      return ZoneRegion::kOpen;
  }
  return ZoneRegion::kOpen;
}

}  // namespace groundline::sim
