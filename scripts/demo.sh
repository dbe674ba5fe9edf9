#!/usr/bin/env bash
# README command 1: install what is needed, build groundline, and run the main
# job on the bundled default: simulate a 400 m loop through the high-bay rack
# aisles of zone B (seed 1), replay it through `groundline localize`, and print
# its accuracy against ground truth. When the shared real data is present
# (../shared/data), also score the raw odometry of the ACES CARMEN log against
# its Kuemmerle relations.
#
# Outputs go to out/demo/ (override with GROUNDLINE_DEMO_OUT).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
echo "== building groundline =="
scripts/build.sh release groundline

gl=build/tools/groundline
out="${GROUNDLINE_DEMO_OUT:-out/demo}"
mkdir -p "$out"

echo
echo "== simulating zone B (high-bay rack aisles), 400 m loop, seed 1; floor camera at 0.5 Hz for sample frames =="
"$gl" sim --zone B --length 400m --seed 1 --camera-rate 0.5 --out "$out/zone_b_seed1"

echo
echo "== localizing (mode: odometry; the floor-line and LiDAR modes come with the localization issues) =="
"$gl" localize --dataset "$out/zone_b_seed1" --out "$out/run_odometry"

echo
echo "== accuracy table =="
"$gl" eval --est "$out/run_odometry/trajectory.tum" --label odometry \
  --ref "$out/zone_b_seed1/ground_truth.tum" --json "$out/eval_zone_b_seed1.json"

data="${GROUNDLINE_DATA_DIR:-../shared/data}"
if [ -f "$data/lidar2d/aces.clf.bz2" ] && [ -f "$data/lidar2d/aces.relations" ]; then
  echo
  echo "== real data: raw odometry of the ACES log against the Kuemmerle relations =="
  "$gl" convert carmen "$data/lidar2d/aces.clf.bz2" --out "$out/aces_raw_odometry.tum"
  "$gl" eval --est "$out/aces_raw_odometry.tum" --label aces_raw_odometry \
    --relations "$data/lidar2d/aces.relations" --json "$out/eval_aces.json"
else
  echo
  echo "(shared data not found at $data: skipping the real-log part)"
fi

echo
echo "Outputs in $out: the dataset (zone_b_seed1/, with layout.png), the run"
echo "(run_odometry/: trajectory.tum, health.jsonl, summary.json) and eval JSON files."
