// The per-zone accuracy table of `groundline eval --dataset DIR --run
// LABEL=RUN ...`: one row per run (odometry, lines, lidar, ...,
// whatever run directories are given), the metrics with zone targets, and a
// last column saying whether the row meets the zone's targets.
//
// Targets (docs/metrics.md, "Zone targets"): zone B: ATE RMSE <= 1.5 cm, ATE max <= 5 cm,
// along-track RMSE <= 1.0 cm, heading RMSE <= 0.2 deg, no aisle exit with an error above 5 cm;
// zones A, C, D: ATE RMSE <= 2 cm; every zone: NEES in the 95 % band on >= 90 % of keyframes (when
// the run has covariances).
#ifndef GROUNDLINE_TOOLS_EVAL_ZONE_TABLE_H_
#define GROUNDLINE_TOOLS_EVAL_ZONE_TABLE_H_

#include <string>
#include <vector>

#include "groundline/core/trajectory.h"

#include "groundline/core/metric_fields.h"

namespace groundline::tools {

// One evaluated estimate: its identity and its metric fields in order.
struct EvalRun {
  std::string label;
  std::string est_path;
  std::vector<core::MetricField> fields;
};

// The failed targets of `run` for `zone` ("A".."D"; other names: the A/C/D
// targets), e.g. "ate_rmse", "aisle_exits"; empty if all are met.
std::vector<std::string> FailedZoneTargets(const EvalRun& run, const std::string& zone);

// Prints the table to stdout under a title line naming the zone and dataset.
void PrintZoneTable(const std::string& zone, const std::string& dataset,
                    const std::vector<EvalRun>& runs);

// For the runs given as --run LABEL=DIR whose DIR/health.jsonl has the LiDAR
// degeneracy detector's flag per keyframe (`localize --lidar` or `--mode
// lidar`): one line per run with the share of keyframes flagged in each
// region of the simulated zone (sim/zone_regions.h, at the keyframe's
// reference pose; deeper than 5 m into an aisle or corridor), checked against
// the targets (aisle >= 95 %, open < 5 %; other regions unscored). Prints
// nothing when no run has them or the zone is not A-D.
void PrintDetectorShares(const std::vector<EvalRun>& runs, const core::Trajectory& reference,
                         const std::string& zone);

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_EVAL_ZONE_TABLE_H_
