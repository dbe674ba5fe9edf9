#include "eval_zone_table.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>

#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "groundline/core/trajectory_association.h"
#include "groundline/sim/zone_regions.h"
#include "groundline/sim/zones.h"

namespace groundline::tools {
namespace {

std::optional<double> Field(const EvalRun& run, const std::string& key) {
  for (const core::MetricField& f : run.fields) {
    if (f.key == key) return f.value;
  }
  return std::nullopt;
}

struct Column {
  const char* key;
  const char* header;
  double scale;  // printed value = field * scale
  const char* format;
};
constexpr Column kColumns[] = {
    {"ate_rmse_m", "ATE rmse[cm]", 100.0, "%.2f"},
    {"ate_max_m", "ATE max[cm]", 100.0, "%.2f"},
    {"along_rmse_m", "along rmse[cm]", 100.0, "%.2f"},
    {"cross_rmse_m", "cross rmse[cm]", 100.0, "%.2f"},
    {"heading_rmse_deg", "head rmse[deg]", 1.0, "%.3f"},
    {"aisle_exits_n", "exits", 1.0, "%.0f"},
    {"aisle_exit_max_m", "exit max[cm]", 100.0, "%.2f"},
    {"aisle_exits_above_threshold", "exits>5cm", 1.0, "%.0f"},
    {"nees_mean", "NEES mean", 1.0, "%.2f"},
    {"nees_in_band", "NEES in band[%]", 100.0, "%.1f"},
};

}  // namespace

std::vector<std::string> FailedZoneTargets(const EvalRun& run, const std::string& zone) {
  std::vector<std::string> failed;
  const auto check = [&](const char* key, double limit, bool at_least, const char* name) {
    const std::optional<double> value = Field(run, key);
    if (!value) return;
    if (at_least ? !(*value >= limit) : !(*value <= limit)) failed.push_back(name);
  };
  if (zone == "B") {
    check("ate_rmse_m", 0.015, false, "ate_rmse");
    check("ate_max_m", 0.05, false, "ate_max");
    check("along_rmse_m", 0.010, false, "along_rmse");
    check("heading_rmse_deg", 0.2, false, "heading_rmse");
    check("aisle_exits_above_threshold", 0.0, false, "aisle_exits");
  } else {
    check("ate_rmse_m", 0.02, false, "ate_rmse");
  }
  check("nees_in_band", 0.90, true, "nees");
  return failed;
}

void PrintZoneTable(const std::string& zone, const std::string& dataset,
                    const std::vector<EvalRun>& runs) {
  std::printf("zone %s (%s)\n", zone.c_str(), dataset.c_str());
  std::size_t label_width = 5;
  for (const EvalRun& run : runs) label_width = std::max(label_width, run.label.size());
  std::printf("%-*s", static_cast<int>(label_width), "run");
  for (const Column& c : kColumns) std::printf("  %s", c.header);
  std::printf("  targets\n");
  for (const EvalRun& run : runs) {
    std::printf("%-*s", static_cast<int>(label_width), run.label.c_str());
    for (const Column& c : kColumns) {
      char text[32] = "-";
      if (const std::optional<double> value = Field(run, c.key)) {
        std::snprintf(text, sizeof(text), c.format, *value * c.scale);
      }
      std::printf("  %*s", static_cast<int>(std::string(c.header).size()), text);
    }
    const std::vector<std::string> failed = FailedZoneTargets(run, zone);
    std::string verdict = failed.empty() ? "met" : "missed:";
    for (const std::string& f : failed) verdict += " " + f;
    std::printf("  %s\n", verdict.c_str());
  }
}

void PrintDetectorShares(const std::vector<EvalRun>& runs, const core::Trajectory& reference,
                         const std::string& zone) {
  constexpr double kRegionEndMarginM = 5.0;
  const core::Result<sim::Zone> parsed = sim::ParseZone(zone);
  if (!parsed.ok() || reference.empty()) return;
  bool title = false;
  for (const EvalRun& run : runs) {
    std::ifstream in(std::filesystem::path(run.est_path).parent_path() / "health.jsonl");
    if (!in) continue;
    // Per region: keyframes, flagged degenerate.
    std::map<std::string, std::pair<int, int>> regions;
    std::string text;
    while (std::getline(in, text)) {
      const nlohmann::json line = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
      if (line.is_discarded() || !line.contains("lidar_degenerate") || !line.contains("stamp_s")) {
        continue;
      }
      const core::SE2 truth = core::InterpolatePose(reference, line["stamp_s"].get<double>());
      const std::string region =
          sim::ZoneRegionName(sim::PresetRegionAt(*parsed, truth.translation(), kRegionEndMarginM));
      std::pair<int, int>& counts = regions[region];
      counts.first += 1;
      counts.second += line["lidar_degenerate"].get<bool>() ? 1 : 0;
    }
    if (regions.empty()) continue;
    if (!title) {
      std::printf(
          "LiDAR degeneracy detector, keyframes flagged per region "
          "(targets: aisle >= 95 %%, open < 5 %%)\n");
      title = true;
    }
    std::printf("  %s:", run.label.c_str());
    for (const auto& [region, counts] : regions) {
      const double share = static_cast<double>(counts.second) / counts.first;
      std::string verdict;
      if (region == "aisle") verdict = share >= 0.95 ? " met" : " missed";
      if (region == "open") verdict = share < 0.05 ? " met" : " missed";
      std::printf(" %s %d/%d = %.1f %%%s", region.c_str(), counts.second, counts.first,
                  100.0 * share, verdict.c_str());
    }
    std::printf("\n");
  }
}

}  // namespace groundline::tools
