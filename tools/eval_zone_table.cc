#include "eval_zone_table.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>

#include <nlohmann/json.hpp>

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

void PrintDetectorShares(const std::vector<EvalRun>& runs) {
  bool title = false;
  for (const EvalRun& run : runs) {
    const std::filesystem::path summary_path =
        std::filesystem::path(run.est_path).parent_path() / "summary.json";
    std::ifstream in(summary_path);
    if (!in) continue;
    const nlohmann::json summary = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (summary.is_discarded() || !summary.contains("lidar") ||
        !summary["lidar"].contains("detector")) {
      continue;
    }
    if (!title) {
      std::printf(
          "LiDAR degeneracy detector, keyframes flagged per region "
          "(issue 7: aisle >= 95 %%, open < 5 %%)\n");
      title = true;
    }
    std::printf("  %s:", run.label.c_str());
    for (const auto& [region, counts] : summary["lidar"]["detector"].items()) {
      const double share = counts.value("fraction_flagged", 0.0);
      std::string verdict;
      if (region == "aisle") verdict = share >= 0.95 ? " met" : " missed";
      if (region == "open") verdict = share < 0.05 ? " met" : " missed";
      std::printf(" %s %d/%d = %.1f %%%s", region.c_str(), counts.value("flagged_degenerate", 0),
                  counts.value("keyframes", 0), 100.0 * share, verdict.c_str());
    }
    std::printf("\n");
  }
}

}  // namespace groundline::tools
