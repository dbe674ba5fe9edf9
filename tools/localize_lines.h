// `groundline localize --mode lines|mapping`: the floor-line factor graph on a
// dataset: camera frames -> BEV -> lines (perception/line_extractor.h) ->
// the sliding-window smoother (localization/sliding_window_smoother.h) with
// wheel odometry between keyframes.
#ifndef GROUNDLINE_TOOLS_LOCALIZE_LINES_H_
#define GROUNDLINE_TOOLS_LOCALIZE_LINES_H_

#include <string>
#include <vector>

namespace groundline::tools {

struct LocalizeLinesFlags {
  std::string dataset_dir;
  std::string out_dir;
  bool mapping = false;              // build the atlas instead of localizing on one
  std::string atlas_path;            // localization: the atlas (default: the dataset's floor map)
  std::string atlas_out_path;        // mapping: where to write it (default OUT/atlas.json)
  std::vector<double> initial_pose;  // x_m y_m yaw_deg
  double window_s = 120.0;
  // With ground truth: per-keyframe errors and an association check in
  // health.jsonl (localize_diagnostics.h).
  bool diagnose = false;
  // > 0: the odometry noise model of independent wheel errors of this
  // variance per metre of wheel travel (OdometryNoiseFromWheelVariance);
  // 0: the OdometryNoiseParams defaults. The default is the simulator's
  // encoder noise (1e-5 m^2/m, sim_run.h) with an allowance for its 0.1 %
  // wheel radius errors (a heading bias of ~0.1 deg/m on a 0.76 m track):
  // with the OdometryNoiseParams defaults (20x the heading variance) the
  // covariance was 3-4x too wide, NEES in band on 44 % of the keyframes
  // (zone D, 200 m); with this 93 %.
  double wheel_variance_m2_per_m = 1.5e-5;
  // With wheel_variance_m2_per_m > 0: the lateral variance per metre
  // travelled [m^2/m] (OdometryNoiseParams::k_lat). The default stands in
  // for what the Gaussian wheel model lacks: a wheel slip (simulator: one per
  // 500 m, ~5 cm) turns the heading by ~4 deg at once, and in zone B's aisles
  // and zone D's corridors nothing the camera sees measures the lateral
  // offset that builds up until the next transverse line fixes the heading.
  // On the 1.2 km zone B run 1e-3 (vs 1e-5) let the aisle tapes seen while
  // turning into an aisle pass the gate: ATE RMSE 49 -> 22 cm, NEES in band
  // 63 -> 82 %; on 200 m zone B / D runs (no slip) neutral.
  double lateral_variance_m2_per_m = 1.0e-3;
  // The association gate (floor_association.h), chi-square 2 dof.
  double gate_chi2 = 9.21;
  // Find the start pose on the atlas (tools/localize_relocalize.h) instead of
  // --initial-pose / the ground truth; near: optional x_m y_m [radius_m] of
  // where the drive starts, which a repeating floor needs.
  bool relocalize = false;
  std::vector<double> near;
  bool lidar = false;  // lines: add the LiDAR scan-match factor (localize_lidar.h)
  // lines: the localization-mode window solver, "chain" (block elimination,
  // the default) or "ceres" (the reference; SmootherSolver).
  std::string solver = "chain";
  // > 0: replay only this many seconds of data after the start.
  double max_duration_s = 0.0;
  // With lidar: rack faces / walls in the scans as line observations against
  // the atlas' wall lines (localize_walls.h).
  bool wall_lines = true;
};

// Exit code: 0 ok, 1 data failure (named on stderr).
int RunLocalizeLines(const LocalizeLinesFlags& flags);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_LOCALIZE_LINES_H_
