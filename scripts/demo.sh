#!/usr/bin/env bash
# README command 1: install what is needed, build groundline, and run the main
# job on the bundled default: simulate 400 m through the high-bay rack aisles
# of zone B (seed 1, floor camera at 2 Hz), run the localization service
# (`groundline serve` with samples/config/serve_replay.yaml) on it replayed 10x
# faster than real time, replay it through `groundline localize` (floor lines
# and odometry; the odometry-only baseline), and print the accuracies side by
# side against ground truth.
# When the shared real data is present (../shared/data), also run the LiDAR
# SLAM on the ACES CARMEN log and score it and the raw odometry against the
# log's Kuemmerle relations.
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
echo "== simulating zone B (high-bay rack aisles), 400 m, seed 1; floor camera at 2 Hz =="
"$gl" sim --zone B --length 400m --seed 1 --camera-rate 2 --out "$out/zone_b_seed1"

echo
echo "== the localization service: floor lines + wheel odometry + LiDAR, the dataset replayed 10x faster"
echo "   than real time (its status page is on 127.0.0.1 while it runs; the port is printed) =="
# samples/config/serve_replay.yaml with this run's paths.
abs_out="$(realpath -m "$out")"
sed -e "s|dataset: .*#|dataset: $abs_out/zone_b_seed1   #|" -e "s|dir: .*run_service|dir: $abs_out/run_service|" \
  -e "s|port: 8088 |port: 0    |" \
  samples/config/serve_replay.yaml > "$out/serve.yaml"
"$gl" serve --config "$out/serve.yaml"

echo
echo "== localizing: floor lines + wheel odometry (sliding-window factor graph on the surveyed floor map) =="
"$gl" localize --dataset "$out/zone_b_seed1" --mode lines --out "$out/run_lines"

echo
echo "== localizing: the full system, floor lines + wheel odometry + LiDAR (scan matching that keeps only"
echo "   the directions the scan constrains, and rack faces as lines against the atlas) =="
"$gl" localize --dataset "$out/zone_b_seed1" --mode lines --lidar --out "$out/run_full"
echo
echo "== localizing: wheel odometry only (the baseline) =="
"$gl" localize --dataset "$out/zone_b_seed1" --out "$out/run_odometry"

echo
echo "== accuracy table =="
"$gl" eval --est "$out/run_service/trajectory.tum" --est "$out/run_full/trajectory.tum" \
  --est "$out/run_lines/trajectory.tum" --est "$out/run_odometry/trajectory.tum" \
  --label service --label lines_lidar --label lines --label odometry \
  --ref "$out/zone_b_seed1/ground_truth.tum" --json "$out/eval_zone_b_seed1.json"

data="${GROUNDLINE_DATA_DIR:-../shared/data}"
if [ -f "$data/lidar2d/aces.clf.bz2" ] && [ -f "$data/lidar2d/aces.relations" ]; then
  echo
  echo "== real data: LiDAR SLAM on the ACES log, and its raw odometry, against the Kuemmerle relations =="
  "$gl" localize --carmen "$data/lidar2d/aces.clf.bz2" --out "$out/run_aces_lidar"
  "$gl" convert carmen "$data/lidar2d/aces.clf.bz2" --out "$out/aces_raw_odometry.tum"
  "$gl" eval --est "$out/run_aces_lidar/trajectory.tum" --est "$out/aces_raw_odometry.tum" \
    --label lidar_slam --label raw_odometry \
    --relations "$data/lidar2d/aces.relations" --json "$out/eval_aces.json"
else
  echo
  echo "(shared data not found at $data: skipping the real-log part)"
fi

echo
echo "Outputs in $out: the dataset (zone_b_seed1/, with layout.png and sample frames), the runs"
echo "(run_full/, run_lines/, run_odometry/, run_aces_lidar/: trajectory.tum, health.jsonl, summary.json)"
echo "and the eval JSON files."
