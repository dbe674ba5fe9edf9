#include "groundline/sim/zones.h"

#include <cctype>
#include <string>

namespace groundline::sim {

core::Result<Zone> ParseZone(std::string_view name) {
  if (name.size() == 1) {
    switch (std::toupper(static_cast<unsigned char>(name[0]))) {
      case 'A':
        return Zone::kA;
      case 'B':
        return Zone::kB;
      case 'C':
        return Zone::kC;
      case 'D':
        return Zone::kD;
      default:
        break;
    }
  }
  return core::Status::Error("zone: expected one of A, B, C, D, got '" + std::string(name) + "'");
}

core::Result<World> BuildZone(Zone zone, std::uint64_t seed) {
  switch (zone) {
    case Zone::kA: {
      ZoneAOptions options;
      options.seed = seed;
      return BuildZoneA(options);
    }
    case Zone::kB: {
      ZoneBOptions options;
      options.seed = seed;
      return BuildZoneB(options);
    }
    case Zone::kC: {
      ZoneCOptions options;
      options.seed = seed;
      return BuildZoneC(options);
    }
    case Zone::kD: {
      ZoneDOptions options;
      options.seed = seed;
      return BuildZoneD(options);
    }
  }
  return core::Status::Error("BuildZone: unknown zone");
}

}  // namespace groundline::sim
