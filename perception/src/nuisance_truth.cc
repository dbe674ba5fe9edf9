#include "groundline/perception/nuisance_truth.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "groundline/core/segment_distance.h"

namespace groundline::perception {
namespace {

Eigen::Vector2d ReadPoint(const nlohmann::json& j) {
  if (!j.is_array() || j.size() != 2 || !j[0].is_number() || !j[1].is_number()) {
    throw std::runtime_error("expected a point [x, y]");
  }
  return {j[0].get<double>(), j[1].get<double>()};
}

}  // namespace

std::vector<NuisanceLine> NuisanceTruth::InView(const core::SE2& T_map_base,
                                                const std::string& file, double radius_m) const {
  std::vector<NuisanceLine> out;
  const core::SE2 T_base_map = T_map_base.Inverse();
  const Eigen::Vector2d origin = T_map_base.translation();
  for (const NuisanceLine& n : map_segments) {
    if (core::DistanceToSegment(origin, n.a_m, n.b_m) > radius_m) continue;
    out.push_back({n.cls, T_base_map * n.a_m, T_base_map * n.b_m});
  }
  if (const auto it = frame_segments.find(file); it != frame_segments.end()) {
    out.insert(out.end(), it->second.begin(), it->second.end());
  }
  return out;
}

core::Result<NuisanceTruth> ReadNuisanceTruth(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return core::Status::Error(path.string() + ": cannot be read");
  std::string field = "(the file)";
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    field = "format";
    if (j.at("format") != "groundline-nuisance-truth") {
      throw std::runtime_error("expected groundline-nuisance-truth");
    }
    NuisanceTruth truth;
    field = "segments_map";
    for (const nlohmann::json& s : j.at("segments_map")) {
      truth.map_segments.push_back(
          {s.at("class").get<std::string>(), ReadPoint(s.at("a_m")), ReadPoint(s.at("b_m"))});
    }
    field = "vehicle_shadow_per_frame";
    for (const nlohmann::json& f : j.at("vehicle_shadow_per_frame")) {
      const nlohmann::json& polygon = f.at("polygon_base");
      std::vector<NuisanceLine>& lines = truth.frame_segments[f.at("file").get<std::string>()];
      for (std::size_t k = 0; k < polygon.size(); ++k) {
        lines.push_back({"vehicle_shadow_edge", ReadPoint(polygon[k]),
                         ReadPoint(polygon[(k + 1) % polygon.size()])});
      }
    }
    field = "standing_objects_per_frame";  // optional: older files lack it
    if (j.contains("standing_objects_per_frame")) {
      for (const nlohmann::json& f : j.at("standing_objects_per_frame")) {
        std::vector<NuisanceLine>& lines = truth.frame_segments[f.at("file").get<std::string>()];
        for (const nlohmann::json& s : f.at("segments_base")) {
          if (!s.is_array() || s.size() != 4) throw std::runtime_error("expected [ax, ay, bx, by]");
          lines.push_back({"standing_object",
                           {s[0].get<double>(), s[1].get<double>()},
                           {s[2].get<double>(), s[3].get<double>()}});
        }
      }
    }
    return truth;
  } catch (const std::exception& e) {
    return core::Status::Error(path.string() + ": field '" + field + "': " + e.what());
  }
}

}  // namespace groundline::perception
