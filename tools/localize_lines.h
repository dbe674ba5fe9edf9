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
  // random wheel travel error (sim_run.h, 1e-5 m^2/m). Its slips (~5 cm on
  // one wheel every 500 m) are not spread into it as a Gaussian equivalent
  // (which was 1.27e-5): between slips, i.e. nearly always, that made every
  // keyframe's covariance too wide, while a slip itself is far in any
  // Gaussian's tail and is handled by the gate's slip hypothesis
  // (slip_sigma_m). Its 0.1 % wheel radius errors add 0.75 mm per 0.75 m
  // keyframe, below the random 1.9 mm, and are left out. Against a Monte
  // Carlo of the simulator's encoders (slips included) over keyframe-length
  // motions (tests/sim/keyframe_odometry_noise_test.cc), with the lateral
  // variance below and the smoother's floors: per-component NEES 0.93-1.30,
  // joint 3.2 straight and 2.7 turning (3 expected); with 1.27e-5, 1e-6 and
  // the former 1 mm floor 0.64-1.00, joint 2.1 and 1.8.
  double wheel_variance_m2_per_m = 1.0e-5;
  // With wheel_variance_m2_per_m > 0: the lateral variance per metre
  // travelled [m^2/m] (OdometryNoiseParams::k_lat). The simulator (and a
  // differential drive without side slip) has no lateral error source: the
  // lateral error between keyframes is the heading error carried along,
  // which the integrator propagates; 1e-7 (0.3 mm per sqrt(m), the size of
  // the smoother's per-keyframe floor) only keeps the increment invertible.
  // The former 1e-3 made the lateral variance ~100x too wide
  // (tests/sim/keyframe_odometry_noise_test.cc); it had held the gate open
  // after a wheel slip (a heading jump), which the slip hypothesis of the
  // gate (slip_sigma_m) now does.
  double lateral_variance_m2_per_m = 1.0e-7;
  // The slip hypothesis of the association gate
  // (SmootherOptions::slip_sigma_m) [m]: the RMS spurious travel of the
  // simulator's slips, 5 cm x U[0.5, 1.5] (sim_run.h): 5.2 cm. 0: off.
  double slip_sigma_m = 0.052;
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
