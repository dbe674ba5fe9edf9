// `groundline eval`: trajectory accuracy of one or more estimates against a
// reference trajectory and/or Kuemmerle relations (docs/metrics.md).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "eval_zone_table.h"
#include "groundline/core/aisle_exits.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/floor_map.h"
#include "groundline/core/metric_fields.h"
#include "groundline/core/relation_metrics.h"
#include "groundline/core/trajectory_covariance_io.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/core/trajectory_metrics.h"
#include "groundline/io/relations.h"
#include "groundline/localization/atlas.h"
#include "groundline/localization/atlas_accuracy.h"

namespace groundline::tools {
namespace {

struct EvalFlags {
  std::vector<std::string> est_paths;
  std::vector<std::string> labels;
  std::string ref_path;
  std::string relations_path;
  bool align = false;
  std::string assoc = "nearest";
  double max_dt_s = 0.01;
  std::optional<double> rpe_m;
  std::optional<int> rpe_frames;
  std::string json_path;
  std::vector<std::string> runs;  // LABEL=DIR
  std::string dataset_dir;
  std::string zone;
  std::string floor_map_path;
  std::string atlas_path;
  // Only the estimate poses with stamps in [from, to) (a window after a fault).
  std::optional<double> from_s;
  std::optional<double> to_s;
};

constexpr char kEvalHelp[] =
    R"(Measures the accuracy of estimated trajectories (formulas in docs/metrics.md).

Reads TUM ('t x y z qx qy qz qw', t in s) or EuRoC (.csv, t in ns) trajectories and
compares each --est with a reference trajectory (--ref) and/or Kuemmerle relations
(--relations, lines 't1 t2 x y z roll pitch yaw'); at least one of the two.

Against --ref: poses are matched by timestamp (--assoc nearest: the reference pose
nearest in time within --max-dt-s; interp: the reference interpolated on SE(2)),
unmatched estimate poses are counted. ATE RMSE/mean/median/max [m] in the map frame
(no alignment unless --align: closed-form SE(2) least squares, no scale, reported
as align_x_m/align_y_m/align_yaw_deg), along-track (slip) and cross-track RMSE [m]
relative to the reference direction of travel, heading RMSE [deg], NEES when the
estimate carries covariances, RPE with --rpe-m or --rpe-frames.
Against --relations: for each relation the estimate poses nearest t1 and t2 (within
--max-dt-s); mean and population std of the translational [m] and rotational [deg]
error of delta_ref^-1 * delta_est.

Prints a table (one column per estimate). --json writes, atomically, one object per
estimate with the keys of docs/metrics.md plus label, est, ref, relations, assoc, max_dt_s,
aligned: a single object for one --est, a JSON array of such objects (in --est
order) for several.

Runs and datasets: --run LABEL=DIR takes DIR/trajectory.tum of a `groundline
localize` output and, when present, DIR/trajectory_covariance.txt (the NEES);
--dataset DIR takes the dataset's ground truth as the reference and its floor map
for the aisle exits (core/aisle_exits.h: the first ground-truth sample outside an
aisle between two parallel solid tapes after >= 10 m inside it; error = |p_est -
p_ref| there, the estimate interpolated; counted above 5 cm). --floor-map FILE does
the same with --ref. --zone A|B|C|D prints instead one compact table, one row per
run (ATE rmse/max, along/cross-track rmse in cm, heading rmse in deg, aisle exits,
NEES mean and share in the 95 % band), each row checked against the localization
targets of the zone (B: ATE rmse <= 1.5 cm, max <= 5 cm, along <= 1 cm, heading
<= 0.2 deg, no exit above 5 cm; A, C, D: ATE rmse <= 2 cm; all: NEES in band on
>= 90 % of the keyframes); under it, for runs made with the LiDAR, the share of
keyframes its degeneracy detector flagged per region (aisle >= 95 %, open < 5 %).
scripts/eval_zones.sh runs every mode on every zone.

--atlas FILE (with --dataset DIR or --floor-map FILE, no --est or --run)
compares a built atlas with the atlas of the floor map: each built line is
paired with the nearest map line of its family (floor marking, or wall and
rack face) whose extent overlaps it, within 30 cm (its middle's offset from
the map line) and 2 deg, each junction with the nearest map junction within
30 cm; per family the median offset ('rho') and |alpha| error, the largest
offset, and the share of paired landmarks
whose error is inside their reported 3 sigma. A floor map written with
--survey-noise is itself off by its survey errors. Exit 1 when nothing pairs.

Examples:
  groundline eval --dataset sim/B --zone B --run odometry=runs/B/odometry \
      --run lines=runs/B/lines
  groundline eval --est run1/trajectory.tum --est run2/trajectory.tum \
      --label floor --label lidar_only --ref gt.tum --align --json eval.json
  groundline eval --est aces_odom.tum --relations aces.relations
  groundline eval --dataset sim/B --atlas run_map/atlas.json
Exit codes: 0 ok, 1 unreadable input or no match, 2 usage error.)";

std::string DefaultLabel(const std::string& path, const std::vector<std::string>& all) {
  const std::string stem = std::filesystem::path(path).stem().string();
  int same = 0;
  for (const std::string& other : all) {
    if (std::filesystem::path(other).stem().string() == stem) ++same;
  }
  return same > 1 ? path : stem;
}

nlohmann::ordered_json RunToJson(const EvalRun& run, const EvalFlags& flags) {
  nlohmann::ordered_json object;
  object["label"] = run.label;
  object["est"] = run.est_path;
  if (!flags.ref_path.empty()) {
    object["ref"] = flags.ref_path;
    object["assoc"] = flags.assoc;
    object["aligned"] = flags.align;
  }
  if (!flags.relations_path.empty()) object["relations"] = flags.relations_path;
  object["max_dt_s"] = flags.max_dt_s;
  for (const core::MetricField& field : run.fields) {
    if (field.is_count) {
      object[field.key] = static_cast<std::uint64_t>(field.value);
    } else {
      object[field.key] = field.value;
    }
  }
  return object;
}

// Rows are the union of the runs' fields, in first-seen order; "-" where a run lacks one.
void PrintTable(const std::vector<EvalRun>& runs) {
  std::vector<std::pair<std::string, std::string>> rows;  // key, label
  std::vector<std::map<std::string, std::string>> cells(runs.size());
  std::size_t label_width = 6;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    for (const core::MetricField& field : runs[r].fields) {
      bool known = false;
      for (const auto& row : rows) known = known || row.first == field.key;
      if (!known) rows.emplace_back(field.key, field.label);
      char text[64];
      std::snprintf(text, sizeof(text), field.is_count ? "%.0f" : "%.4f", field.value);
      cells[r][field.key] = text;
      label_width = std::max(label_width, field.label.size());
    }
  }
  std::vector<std::size_t> widths;
  std::printf("%-*s", static_cast<int>(label_width), "metric");
  for (const EvalRun& run : runs) {
    widths.push_back(std::max<std::size_t>(12, run.label.size()));
    std::printf("  %*s", static_cast<int>(widths.back()), run.label.c_str());
  }
  std::printf("\n");
  for (const auto& [key, label] : rows) {
    std::printf("%-*s", static_cast<int>(label_width), label.c_str());
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const auto it = cells[r].find(key);
      std::printf("  %*s", static_cast<int>(widths[r]),
                  it == cells[r].end() ? "-" : it->second.c_str());
    }
    std::printf("\n");
  }
}

// A dataset's ground truth and floor map (no sensor streams).
core::Result<core::Dataset> ReadTruth(const std::string& dir) {
  core::DatasetReadOptions read_options;
  read_options.load_images = false;
  read_options.check_image_files = false;
  read_options.load_wheel_encoders = false;
  read_options.load_scans = false;
  return core::ReadDataset(dir, read_options);
}

// --atlas: a built atlas against the floor map's (the dataset's or --floor-map).
int RunAtlasEval(const EvalFlags& flags) {
  if (!flags.est_paths.empty() || !flags.runs.empty()) {
    std::fprintf(stderr, "groundline eval: --atlas takes no --est or --run\n");
    return 2;
  }
  std::optional<core::FloorMap> map;
  std::string map_name = flags.floor_map_path;
  if (!flags.floor_map_path.empty()) {
    core::Result<core::FloorMap> read = core::ReadFloorMap(flags.floor_map_path);
    if (!read.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", read.message().c_str());
      return 1;
    }
    map = std::move(read).value();
  } else if (!flags.dataset_dir.empty()) {
    core::Result<core::Dataset> dataset = ReadTruth(flags.dataset_dir);
    if (!dataset.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", dataset.message().c_str());
      return 1;
    }
    map = std::move(dataset->floor_map);
    map_name = flags.dataset_dir + "'s floor map";
  }
  if (!map) {
    std::fprintf(stderr, "groundline eval: --atlas needs --dataset DIR or --floor-map FILE\n");
    return 2;
  }
  core::Result<localization::Atlas> built = localization::ReadAtlas(flags.atlas_path);
  if (!built.ok()) {
    std::fprintf(stderr, "groundline eval: %s\n", built.message().c_str());
    return 1;
  }
  const localization::Atlas reference =
      localization::AtlasFromFloorMap(*map, localization::AtlasFromFloorMapOptions{});
  const localization::AtlasAccuracy a = localization::CompareAtlases(*built, reference);
  std::printf("%s against %s:\n", flags.atlas_path.c_str(), map_name.c_str());
  std::printf("%-12s %7s %7s %14s %16s %13s %12s\n", "landmarks", "built", "paired", "median |rho|",
              "median |alpha|", "max |rho|", "within 3 sd");
  nlohmann::ordered_json json;
  for (const auto& [name, l] :
       {std::pair<const char*, const localization::LandmarkAccuracy&>{"floor lines", a.floor_lines},
        {"faces", a.faces},
        {"junctions", a.junctions}}) {
    std::printf("%-12s %7d %7d %11.1f mm %12.3f deg %10.1f mm %11.1f %%\n", name, l.built, l.paired,
                1e3 * l.median_abs_rho_m, l.median_abs_alpha_rad * 180.0 / 3.14159265358979,
                1e3 * l.max_abs_rho_m, 100.0 * l.within_3_sigma);
    json[name] = {{"built", l.built},
                  {"paired", l.paired},
                  {"median_abs_rho_m", l.median_abs_rho_m},
                  {"median_abs_alpha_rad", l.median_abs_alpha_rad},
                  {"max_abs_rho_m", l.max_abs_rho_m},
                  {"within_3_sigma", l.within_3_sigma}};
  }
  if (!flags.json_path.empty()) {
    if (core::Status s = core::WriteFileAtomically(flags.json_path, json.dump(2) + "\n"); !s.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", s.message().c_str());
      return 1;
    }
  }
  return a.floor_lines.paired + a.faces.paired > 0 ? 0 : 1;
}

int RunEval(EvalFlags flags) {
  if (!flags.atlas_path.empty()) return RunAtlasEval(flags);
  if (flags.est_paths.empty() && flags.runs.empty()) {
    std::fprintf(stderr, "groundline eval: give --est FILE or --run LABEL=DIR\n");
    return 2;
  }
  if (!flags.runs.empty() && (!flags.est_paths.empty() || !flags.labels.empty())) {
    std::fprintf(stderr, "groundline eval: --run LABEL=DIR takes no --est or --label\n");
    return 2;
  }
  if (flags.ref_path.empty() && flags.relations_path.empty() && flags.dataset_dir.empty()) {
    std::fprintf(stderr,
                 "groundline eval: give --ref FILE, --dataset DIR and/or --relations FILE\n");
    return 2;
  }
  std::vector<std::string> covariance_paths(flags.est_paths.size());
  for (const std::string& run : flags.runs) {
    const std::size_t eq = run.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == run.size()) {
      std::fprintf(stderr, "groundline eval: --run '%s': expected LABEL=DIR\n", run.c_str());
      return 2;
    }
    const std::filesystem::path dir = run.substr(eq + 1);
    flags.labels.push_back(run.substr(0, eq));
    flags.est_paths.push_back((dir / "trajectory.tum").string());
    const std::filesystem::path covariance = dir / "trajectory_covariance.txt";
    covariance_paths.push_back(std::filesystem::exists(covariance) ? covariance.string() : "");
  }
  if (!flags.labels.empty() && flags.labels.size() != flags.est_paths.size()) {
    std::fprintf(stderr, "groundline eval: %zu --label for %zu --est; give one per --est or none\n",
                 flags.labels.size(), flags.est_paths.size());
    return 2;
  }
  core::TrajectoryMetricsOptions options;
  options.align = flags.align;
  options.association.max_dt_s = flags.max_dt_s;
  options.association.method = flags.assoc == "interp" ? core::AssociationMethod::kInterpolate
                                                       : core::AssociationMethod::kNearest;
  if (flags.rpe_m) options.rpe = core::RpeOptions{core::RpeDeltaUnit::kMetres, *flags.rpe_m};
  if (flags.rpe_frames) {
    options.rpe =
        core::RpeOptions{core::RpeDeltaUnit::kFrames, static_cast<double>(*flags.rpe_frames)};
  }
  core::RelationMetricsOptions relation_options;
  relation_options.max_dt_s = flags.max_dt_s;
  for (const core::Status& s : {options.Validate(), relation_options.Validate()}) {
    if (!s.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", s.message().c_str());
      return 2;
    }
  }

  std::optional<core::Trajectory> reference;
  std::optional<core::FloorMap> floor_map;
  if (!flags.dataset_dir.empty()) {
    core::Result<core::Dataset> dataset = ReadTruth(flags.dataset_dir);
    if (!dataset.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", dataset.message().c_str());
      return 1;
    }
    if (dataset->ground_truth.empty()) {
      std::fprintf(stderr, "groundline eval: %s: the dataset has no ground truth\n",
                   flags.dataset_dir.c_str());
      return 1;
    }
    reference = std::move(dataset->ground_truth);
    floor_map = std::move(dataset->floor_map);
  }
  if (!flags.floor_map_path.empty()) {
    core::Result<core::FloorMap> read = core::ReadFloorMap(flags.floor_map_path);
    if (!read.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", read.message().c_str());
      return 1;
    }
    floor_map = std::move(read).value();
  }
  if (!flags.ref_path.empty()) {
    core::Result<core::Trajectory> read = core::ReadTrajectory(flags.ref_path);
    if (!read.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", read.message().c_str());
      return 1;
    }
    reference = std::move(read).value();
  }
  std::optional<std::vector<core::Relation>> relations;
  if (!flags.relations_path.empty()) {
    core::Result<std::vector<core::Relation>> read = io::ReadRelations(flags.relations_path);
    if (!read.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", read.message().c_str());
      return 1;
    }
    relations = std::move(read).value();
  }

  std::vector<EvalRun> runs;
  for (std::size_t i = 0; i < flags.est_paths.size(); ++i) {
    const std::string& path = flags.est_paths[i];
    EvalRun run{
        flags.labels.empty() ? DefaultLabel(path, flags.est_paths) : flags.labels[i], path, {}};
    core::Result<core::Trajectory> estimate = core::ReadTrajectory(path);
    if (!estimate.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", estimate.message().c_str());
      return 1;
    }
    if (!covariance_paths[i].empty()) {
      if (core::Status s = core::AttachTrajectoryCovariances(covariance_paths[i], &*estimate);
          !s.ok()) {
        std::fprintf(stderr, "groundline eval: %s\n", s.message().c_str());
        return 1;
      }
    }
    if (flags.from_s || flags.to_s) {
      std::erase_if(*estimate, [&flags](const core::StampedPose& p) {
        return (flags.from_s && p.stamp_s < *flags.from_s) ||
               (flags.to_s && p.stamp_s >= *flags.to_s);
      });
      if (estimate->empty()) {
        std::fprintf(stderr, "groundline eval: %s: no pose in the --from-s/--to-s window\n",
                     path.c_str());
        return 1;
      }
    }
    if (reference) {
      core::Result<core::TrajectoryErrorSummary> summary =
          core::ComputeTrajectoryErrors(*estimate, *reference, options);
      if (!summary.ok()) {
        std::fprintf(stderr, "groundline eval: %s vs %s: %s\n", path.c_str(),
                     flags.ref_path.c_str(), summary.message().c_str());
        return 1;
      }
      for (core::MetricField& f : core::MetricFields(*summary)) run.fields.push_back(std::move(f));
      if (floor_map) {
        core::Result<core::AisleExitSummary> exits =
            core::ComputeAisleExitErrors(*estimate, *reference, *floor_map);
        if (!exits.ok()) {
          std::fprintf(stderr, "groundline eval: %s: %s\n", path.c_str(), exits.message().c_str());
          return 1;
        }
        for (core::MetricField& f : core::MetricFields(*exits)) run.fields.push_back(std::move(f));
      }
    }
    if (relations) {
      core::Result<core::RelationErrorSummary> summary =
          core::ComputeRelationErrors(*estimate, *relations, relation_options);
      if (!summary.ok()) {
        std::fprintf(stderr, "groundline eval: %s vs %s: %s\n", path.c_str(),
                     flags.relations_path.c_str(), summary.message().c_str());
        return 1;
      }
      for (core::MetricField& f : core::MetricFields(*summary)) run.fields.push_back(std::move(f));
    }
    runs.push_back(std::move(run));
  }

  if (flags.zone.empty()) {
    PrintTable(runs);
  } else {
    PrintZoneTable(flags.zone, flags.dataset_dir.empty() ? flags.ref_path : flags.dataset_dir,
                   runs);
    PrintDetectorShares(runs, reference.value_or(core::Trajectory()), flags.zone);
  }
  if (!flags.json_path.empty()) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const EvalRun& run : runs) out.push_back(RunToJson(run, flags));
    if (runs.size() == 1) out = out.front();
    if (core::Status s = core::WriteFileAtomically(flags.json_path, out.dump(2) + "\n"); !s.ok()) {
      std::fprintf(stderr, "groundline eval: %s\n", s.message().c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace

CLI::App* AddEvalCommand(CLI::App& parent, CommandRunner* run) {
  CLI::App* cmd = parent.add_subcommand(
      "eval", "Accuracy of trajectories against ground truth or Kuemmerle relations");
  cmd->footer(kEvalHelp);
  auto flags = std::make_shared<EvalFlags>();
  cmd->add_option("--est", flags->est_paths,
                  "estimated trajectory (TUM, or EuRoC if .csv); repeat for several");
  cmd->add_option("--run", flags->runs,
                  "LABEL=DIR: a `groundline localize` output directory (its trajectory.tum, "
                  "and trajectory_covariance.txt for the NEES when present); repeat for rows");
  cmd->add_option("--dataset", flags->dataset_dir,
                  "dataset directory: its ground truth is the reference and its floor map "
                  "gives the aisle exits");
  cmd->add_option("--floor-map", flags->floor_map_path,
                  "floor_map.yaml for the aisle-exit errors (with --ref)");
  cmd->add_option("--zone", flags->zone,
                  "print the compact zone table (one row per run) checked against this zone's "
                  "accuracy targets (docs/metrics.md): A, B, C or D")
      ->check(CLI::IsMember({"A", "B", "C", "D"}));
  cmd->add_option("--atlas", flags->atlas_path,
                  "a built atlas (a mapping run's) to compare with the floor map of --dataset "
                  "or --floor-map, landmark by landmark")
      ->check(CLI::ExistingFile);
  cmd->add_option("--ref", flags->ref_path, "reference trajectory (TUM, or EuRoC if .csv)");
  cmd->add_option("--relations", flags->relations_path,
                  "Kuemmerle relations file ('t1 t2 x y z roll pitch yaw' per line)");
  cmd->add_flag("--align", flags->align,
                "fit and apply an SE(2) alignment (rotation + translation, no scale) before ATE");
  cmd->add_option("--assoc", flags->assoc, "timestamp association: nearest or interp")
      ->check(CLI::IsMember({"nearest", "interp"}))
      ->capture_default_str();
  cmd->add_option("--max-dt-s", flags->max_dt_s,
                  "largest time offset for a match [s] (also for relation stamps)")
      ->capture_default_str();
  cmd->add_option("--from-s", flags->from_s,
                  "score only the estimate poses stamped at or after this time [s] "
                  "(e.g. the minute after a sensor came back)");
  cmd->add_option("--to-s", flags->to_s,
                  "score only the estimate poses stamped before this time [s]");
  CLI::Option* rpe_m = cmd->add_option("--rpe-m", flags->rpe_m,
                                       "also report RPE over this reference path length [m]");
  cmd->add_option("--rpe-frames", flags->rpe_frames,
                  "also report RPE over this many matched poses (a positive integer)")
      ->excludes(rpe_m);
  cmd->add_option("--label", flags->labels,
                  "column name of each --est, in order (default: the file stem)");
  cmd->add_option("--json", flags->json_path, "write the metrics as JSON to this file");
  cmd->callback([flags, run] { *run = [flags] { return RunEval(*flags); }; });
  return cmd;
}

}  // namespace groundline::tools
