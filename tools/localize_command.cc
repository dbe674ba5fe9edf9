// `groundline localize`: replays a dataset through the localization pipeline
// and writes the run outputs of EVAL.md (trajectory.tum, health.jsonl,
// summary.json); prints the accuracy when the dataset has ground truth.

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset.h"
#include "groundline/core/trajectory_covariance_io.h"
#include "groundline/core/trajectory_io.h"
#include "groundline/localization/dead_reckoning.h"
#include "localize_carmen.h"
#include "localize_lidar.h"
#include "localize_lines.h"
#include "run_summary.h"

namespace groundline::tools {
namespace {

struct LocalizeFlags {
  std::string dataset_dir;
  std::string out_dir;
  std::string mode = "odometry";
  std::vector<double> initial_pose;  // x_m, y_m, yaw_deg
};

constexpr char kHelp[] =
    R"(Replays a groundline dataset (docs/dataset.md) and estimates T_map_base.

Modes:
  odometry  dead reckoning of the wheel encoders (differential drive, covariance
            growing with distance and rotation; keyframes every 0.20 m or 5 deg):
            the odometry-only baseline row of every accuracy table.
  lines     floor lines (camera -> BEV -> lines) + odometry in the sliding-window
            smoother on the atlas (--atlas, default the dataset's floor map);
            with --lidar also a LiDAR scan-match factor between keyframes that
            keeps only the directions the scan constrains (not along an aisle).
  mapping   the same, building the atlas (--atlas-out).
  lidar     LiDAR + odometry only: scan-to-submap matching (local SLAM, no loop
            closures) with the odometry as the initial guess, keyframes every
            0.20 m or 5 deg. Health per keyframe: lidar_degenerate, the scaled
            information eigenvalues [1/m^2] and the weakest direction (x, y, theta;
            also in the map frame); on simulated datasets the keyframe's
            ground-truth region (aisle, open, ...) and, in summary.json, the
            share of keyframes flagged degenerate per region.
  --carmen LOG  2D LiDAR + odometry SLAM (submaps, scan-to-submap matching,
            pose graph with loop closures) on a CARMEN log; writes trajectory.tum
            (one pose per front-laser scan, at its ipc_timestamp), health.jsonl
            (per scan: match score, information eigenvalues, degenerate flag) and
            summary.json; with --relations FILE also the relation errors.
            Example: groundline localize --carmen aces.clf.bz2 --relations aces.relations --out run_aces

Start pose: --initial-pose x_m y_m yaw_deg, else the dataset's first ground-truth
pose, else the origin of the map. --mode lines --relocalize instead recognizes
it on the atlas: every junction the camera sees, with a line through it, is
matched against every atlas junction; the candidate poses follow the odometry
and are scored on the lines of later frames until one leads every other by a
margin (docs/atlas.md). A floor that repeats (zone B's aisle mouths) stays
ambiguous: --near x_m y_m [radius_m] says roughly where the drive started.

Writes into --out (created if missing; files replaced atomically):
  trajectory.tum               keyframe poses, TUM 't x y z qx qy qz qw'
  trajectory_odometry_rate.tum one pose per encoder reading
  health.jsonl                 one JSON object per keyframe (pose, covariance, path)
  summary.json                 counts, timings (wall and CPU seconds, peak RSS)
and prints ATE / along-track / heading errors and NEES consistency when the dataset
has ground truth (the full table: groundline eval --est OUT/trajectory.tum --ref ...).

Examples:
  groundline localize --dataset sample_zone_b --out run_odom
  groundline localize --dataset sample_zone_b --mode lines --out run_lines
  groundline localize --dataset sample_zone_b --mode lines --relocalize --near 2 40 --out run_reloc
  groundline localize --dataset sample_zone_b --mode lidar --out run_lidar
  groundline localize --dataset sample_zone_b --mode lines --lidar --out run_lines_lidar
  groundline localize --dataset survey_drive --mode mapping --atlas-out atlas.json --out run_map
  groundline localize --carmen aces.clf.bz2 --relations aces.relations --out run_aces)";

core::Status WriteHealth(const std::filesystem::path& path, const core::Trajectory& keyframes) {
  return core::WriteFileAtomically(path, [&keyframes](std::ostream& out) {
    for (std::size_t k = 0; k < keyframes.size(); ++k) {
      const core::StampedPose& p = keyframes[k];
      nlohmann::ordered_json line;
      line["keyframe"] = k;
      line["stamp_s"] = p.stamp_s;
      line["x_m"] = p.pose.x();
      line["y_m"] = p.pose.y();
      line["yaw_deg"] = p.pose.yaw() * 180.0 / std::numbers::pi;
      line["mode"] = "odometry";
      if (p.covariance) {
        const core::Matrix3& c = *p.covariance;
        line["cov"] = {c(0, 0), c(0, 1), c(0, 2), c(1, 0), c(1, 1),
                       c(1, 2), c(2, 0), c(2, 1), c(2, 2)};
      }
      out << line.dump() << "\n";
    }
    return core::Status::Ok();
  });
}

int Fail(const std::string& message) {
  std::fprintf(stderr, "groundline localize: %s\n", message.c_str());
  return 1;
}

int RunLocalize(const LocalizeFlags& flags) {
  const RunClock clock;
  core::DatasetReadOptions read_options;
  read_options.load_images = false;
  read_options.check_image_files = false;
  read_options.load_scans = false;
  core::Result<core::Dataset> dataset = core::ReadDataset(flags.dataset_dir, read_options);
  if (!dataset.ok()) return Fail(dataset.message());
  const core::DatasetManifest& manifest = dataset->manifest;
  if (!manifest.wheel_encoders || dataset->wheel_encoders.empty()) {
    return Fail(flags.dataset_dir +
                ": the odometry mode needs wheel encoder readings; the "
                "manifest lists none");
  }

  localization::DeadReckoningOptions options;
  options.drive.wheel_radius_m = manifest.wheel_encoders->wheel_radius_m;
  options.drive.track_m = manifest.wheel_encoders->track_m;
  core::StampedPose initial{dataset->wheel_encoders.front().stamp_s, core::SE2(), std::nullopt};
  std::string start_from = "the map origin";
  if (flags.initial_pose.size() == 3) {
    initial.pose = core::SE2(flags.initial_pose[0], flags.initial_pose[1],
                             flags.initial_pose[2] * std::numbers::pi / 180.0);
    start_from = "--initial-pose";
  } else if (!dataset->ground_truth.empty()) {
    initial = dataset->ground_truth.front();
    initial.covariance.reset();
    start_from = "the first ground-truth pose";
  }
  core::Result<localization::DeadReckoningResult> result =
      localization::DeadReckon(dataset->wheel_encoders, initial, options);
  if (!result.ok()) return Fail(flags.dataset_dir + ": " + result.message());

  const std::filesystem::path out(flags.out_dir);
  for (const core::Status& s :
       {core::WriteTumTrajectory(out / "trajectory.tum", result->keyframes),
        core::WriteTumTrajectory(out / "trajectory_odometry_rate.tum", result->odometry_rate),
        core::WriteTrajectoryCovariances(out / "trajectory_covariance.txt", result->keyframes),
        WriteHealth(out / "health.jsonl", result->keyframes)}) {
    if (!s.ok()) return Fail(s.message());
  }
  std::printf("%s: %zu encoder readings, %.1f m driven, %zu keyframes; started at %s\n",
              flags.dataset_dir.c_str(), dataset->wheel_encoders.size(), result->path_length_m,
              result->keyframes.size(), start_from.c_str());

  nlohmann::ordered_json summary;
  summary["dataset"] = flags.dataset_dir;
  summary["mode"] = flags.mode;
  summary["n_keyframes"] = result->keyframes.size();
  summary["n_odometry_poses"] = result->odometry_rate.size();
  summary["path_length_m"] = result->path_length_m;
  const core::Status written =
      FinishRunSummary(result->keyframes, dataset->ground_truth, clock, out, &summary);
  if (!written.ok()) return Fail(written.message());
  std::printf(
      "wrote %s/{trajectory.tum, trajectory_odometry_rate.tum, trajectory_covariance.txt, "
      "health.jsonl, "
      "summary.json}\n",
      flags.out_dir.c_str());
  return 0;
}

}  // namespace

CLI::App* AddLocalizeCommand(CLI::App& parent, CommandRunner* run) {
  auto flags = std::make_shared<LocalizeFlags>();
  CLI::App* cmd = parent.add_subcommand("localize", "Estimate the vehicle pose from a dataset");
  cmd->footer(kHelp);
  cmd->add_option("-d,--dataset", flags->dataset_dir, "Dataset directory (docs/dataset.md)")
      ->check(CLI::ExistingDirectory);
  auto carmen = std::make_shared<LocalizeCarmenFlags>();
  cmd->add_option("--carmen", carmen->log_path,
                  "CARMEN log (.clf[.gz|.bz2]): 2D LiDAR + odometry SLAM instead of --dataset")
      ->check(CLI::ExistingFile)
      ->excludes("--dataset");
  cmd->add_option("--relations", carmen->relations_path,
                  "With --carmen: Kuemmerle .relations file to score the trajectory against")
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", flags->out_dir, "Output directory for the run")->required();
  cmd->add_option("--mode", flags->mode, "Estimator")
      ->check(CLI::IsMember({"odometry", "lines", "mapping", "lidar"}))
      ->capture_default_str();
  cmd->add_option("--initial-pose", flags->initial_pose, "Start pose: x_m y_m yaw_deg")
      ->expected(3);
  auto lines = std::make_shared<LocalizeLinesFlags>();
  cmd->add_option("--atlas", lines->atlas_path,
                  "--mode lines: the atlas to localize on (default: the dataset's floor map)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--atlas-out", lines->atlas_out_path,
                  "--mode mapping: where to write the atlas (default OUT/atlas.json)");
  cmd->add_flag("--diagnose", lines->diagnose,
                "--mode lines: with ground truth, add per-keyframe errors (along/across track, "
                "heading) and an association check (right/wrong/missed lines) to health.jsonl");
  cmd->add_option("--wheel-variance", lines->wheel_variance_m2_per_m,
                  "--mode lines/mapping: odometry noise as independent wheel errors of this "
                  "variance per metre of wheel travel [m^2/m] (0: the OdometryNoiseParams "
                  "defaults)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--lateral-variance", lines->lateral_variance_m2_per_m,
                  "--mode lines/mapping, with --wheel-variance > 0: lateral odometry variance "
                  "per metre travelled [m^2/m] (> 0)")
      ->check(CLI::Range(1e-12, 1.0))
      ->capture_default_str();
  cmd->add_option("--slip-sigma", lines->slip_sigma_m,
                  "--mode lines: RMS spurious travel of a wheel slip [m]; when nothing a "
                  "keyframe sees passes the gate, it is associated again allowing one slip "
                  "(0: off)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--gate-chi2", lines->gate_chi2,
                  "--mode lines/mapping: association gate on the Mahalanobis distance of a line "
                  "(chi-square, 2 dof; 9.21 = 0.99 quantile)")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  cmd->add_option("--window", lines->window_s,
                  "--mode lines/mapping: sliding-window length, seconds")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  cmd->add_flag("--relocalize", lines->relocalize,
                "--mode lines: find the start pose on the atlas from a junction and the lines "
                "around it (no --initial-pose, no ground truth used)");
  cmd->add_option("--near", lines->near,
                  "With --relocalize: x_m y_m [radius_m] where the drive starts (default radius "
                  "2 m); needed where the floor repeats (identical aisle mouths)")
      ->expected(2, 3);
  cmd->add_flag("--lidar", lines->lidar,
                "--mode lines: add the LiDAR scan-match factor (needs lidar_scans) and the "
                "straight faces (rack faces, walls) of the scans as line observations against "
                "the atlas' wall lines");
  cmd->add_flag("--no-wall-lines{false}", lines->wall_lines,
                "--mode lines --lidar: no wall lines (only the scan-match factor)");
  cmd->add_option("--solver", lines->solver,
                  "--mode lines: window solver, chain (exact block elimination of the pose "
                  "chain) or ceres (Levenberg-Marquardt, the reference)")
      ->check(CLI::IsMember({"chain", "ceres"}))
      ->capture_default_str();
  cmd->add_option("--max-duration", lines->max_duration_s,
                  "--mode lines/mapping: replay only this many seconds of data after the start "
                  "(0: all), e.g. --max-duration 150")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  cmd->callback([flags, carmen, lines, run] {
    if (!carmen->log_path.empty()) {
      carmen->out_dir = flags->out_dir;
      *run = [carmen] { return RunLocalizeCarmen(*carmen); };
      return;
    }
    if (flags->dataset_dir.empty()) throw CLI::RequiredError("--dataset or --carmen");
    if (flags->mode != "odometry") {
      lines->dataset_dir = flags->dataset_dir;
      lines->out_dir = flags->out_dir;
      lines->mapping = flags->mode == "mapping";
      lines->initial_pose = flags->initial_pose;
      if (flags->mode == "lidar") {
        *run = [lines] { return RunLocalizeLidar(*lines); };
        return;
      }
      *run = [lines] { return RunLocalizeLines(*lines); };
      return;
    }
    *run = [flags] { return RunLocalize(*flags); };
  });
  return cmd;
}

}  // namespace groundline::tools
