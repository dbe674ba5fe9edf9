#!/usr/bin/env bash
# The per-zone accuracy tables from one command: runs `groundline
# localize` in every mode on every zone dataset, then prints one
# `groundline eval --zone` table per zone (one row per mode, checked against
# the zone's targets).
#
#   scripts/eval_zones.sh [DATA_DIR] [RUNS_DIR]
#     DATA_DIR  holds one dataset per zone: DATA_DIR/A, B, C, D (default /work/simdata)
#     RUNS_DIR  where the runs go: RUNS_DIR/<zone>/<label>/ (default runs/zones)
# Environment:
#   ZONES       zones to evaluate, default "B A C D" (missing datasets are skipped)
#   MODES       ';'-separated LABEL=LOCALIZE-ARGS rows, default
#               "odometry=--mode odometry;lines=--mode lines"; add e.g.
#               "lidar=--mode lidar" or "lines_lidar=--mode lines --lidar"
#   REUSE=1     keep a run whose trajectory.tum exists instead of re-running it
#   GROUNDLINE  the binary (default build/tools/groundline)
# Example:
#   MODES="odometry=--mode odometry;lines=--mode lines" scripts/eval_zones.sh /work/simdata /tmp/runs
set -euo pipefail
data="${1:-/work/simdata}"
runs="${2:-runs/zones}"
bin="${GROUNDLINE:-build/tools/groundline}"
zones="${ZONES:-B A C D}"
modes="${MODES:-odometry=--mode odometry;lines=--mode lines}"
IFS=';' read -r -a rows <<<"$modes"
status=0
for zone in $zones; do
  dataset="$data/$zone"
  if [[ ! -f "$dataset/manifest.yaml" ]]; then
    echo "zone $zone: no dataset at $dataset, skipped" >&2
    continue
  fi
  eval_args=()
  for row in "${rows[@]}"; do
    label="${row%%=*}"
    read -r -a args <<<"${row#*=}"
    out="$runs/$zone/$label"
    if [[ "${REUSE:-0}" != 1 || ! -f "$out/trajectory.tum" ]]; then
      mkdir -p "$out"
      if ! "$bin" localize --dataset "$dataset" "${args[@]}" --out "$out" >"$out/localize.log" 2>&1; then
        echo "zone $zone, $label: localize failed (see $out/localize.log)" >&2
        status=1
        continue
      fi
    fi
    eval_args+=(--run "$label=$out")
  done
  [[ ${#eval_args[@]} -gt 0 ]] || continue
  "$bin" eval --dataset "$dataset" --zone "$zone" "${eval_args[@]}" --assoc interp --max-dt-s 0.05 \
    --json "$runs/$zone/eval.json" || status=1
  echo
done
exit $status
