#!/usr/bin/env bash
# The memory soak: a closed-loop drive replayed through `groundline serve` in
# passes, each shifted in time after the previous one, as one long shift;
# the service's resident memory sampled against the data time it has reached.
#
#   scripts/soak.sh [HOURS] [OUT_DIR]     (default: 8 hours of data, out/soak)
#
# Writes OUT_DIR/rss.tsv (wall s, data h, RSS MB, one line per sample) and,
# at the end, prints RSS at 1 h and at HOURS h of data and the growth between
# them (the service's target: < 5 %). The replay runs as fast as the machine
# allows (`inputs.replay.speed: 0`), so 8 h of data take much less than 8 h.
# The drive has the camera at SOAK_CAMERA_RATE Hz (default 5; 0: no camera),
# so that the camera stage (decoding, the BEV, line extraction) runs through
# the shift as the LiDAR and the estimator do; every frame is extracted, as in
# any replay as fast as possible.
# Environment: GROUNDLINE_BIN (default build/tools/groundline),
# SOAK_SEED (the simulated drive's seed, default 1), SOAK_SAMPLE_S (the mean
# wall time between RSS samples, default 5 s),
# SOAK_CAMERA_RATE (5).
set -euo pipefail
cd "$(dirname "$0")/.."
hours="${1:-8}"
out="${2:-out/soak}"
bin="${GROUNDLINE_BIN:-build/tools/groundline}"
seed="${SOAK_SEED:-1}"
camera_rate="${SOAK_CAMERA_RATE:-5}"
sample_s="${SOAK_SAMPLE_S:-5}"
[ -x "$bin" ] || { echo "soak: $bin is not built (scripts/build.sh release groundline)" >&2; exit 1; }
mkdir -p "$out"
out="$(cd "$out" && pwd)"

dataset="$out/zone_d_loop"
if [ ! -f "$dataset/manifest.yaml" ]; then
  if [ "$camera_rate" = 0 ]; then
    camera=(--no-camera)
    echo "soak: simulating the zone D closed loop (250 m, no camera, seed $seed)"
  else
    camera=(--camera-rate "$camera_rate")
    echo "soak: simulating the zone D closed loop (250 m, camera at $camera_rate Hz, seed $seed)"
  fi
  "$bin" sim --zone D --closed-loop --length 250m "${camera[@]}" --seed "$seed" --out "$dataset" >"$out/sim.log" 2>&1
fi
duration_s=$("$bin" dataset check --skip-scans "$dataset" | awk '$1 == "duration" {print $2}')
[ -n "$duration_s" ] || { echo "soak: could not read the duration of $dataset" >&2; exit 1; }
loops=$(python3 -c "import math,sys; print(math.ceil(float(sys.argv[1])*3600/float(sys.argv[2])))" "$hours" "$duration_s")
echo "soak: ${duration_s} s per pass, $loops passes for $hours h of data"

cat >"$out/serve.yaml" <<EOF
inputs:
  replay:
    dataset: $dataset
    speed: 0
    loops: $loops
localizer:
  preset: fusion
output:
  dir: $out/run
http:
  enabled: false
EOF
rm -rf "$out/run"
"$bin" serve --config "$out/serve.yaml" >"$out/serve.log" 2>&1 &
pid=$!
trap 'kill "$pid" 2>/dev/null || true' EXIT
start=$(date +%s)
t0=""
printf 'wall_s\tdata_h\trss_mb\n' >"$out/rss.tsv"
while kill -0 "$pid" 2>/dev/null; do
  # Jittered by +-50 %: RSS swings by tens of MB within one pass of the loop,
  # and samples at a fixed period lock onto a phase of the pass (a pass
  # takes ~15 s as fast as possible), which a change of replay speed then
  # shifts: a step in the hourly figures that is not the heap's.
  sleep "$(awk -v s="$sample_s" -v r="$RANDOM" 'BEGIN { printf "%.3f", s * (0.5 + r / 32767) }')"
  rss_kb=$(awk '/^VmRSS:/{print $2}' "/proc/$pid/status" 2>/dev/null || true)
  [ -n "$rss_kb" ] || break
  stamp=$(tail -c 8000 "$out/run/health.jsonl" 2>/dev/null | tail -n 1 | grep -o '"stamp_s":[0-9.eE+-]*' | head -n 1 | cut -d: -f2 || true)
  [ -n "$stamp" ] || continue
  [ -n "$t0" ] || t0=$(head -n 1 "$out/run/health.jsonl" | grep -o '"stamp_s":[0-9.eE+-]*' | head -n 1 | cut -d: -f2)
  data_h=$(python3 -c "import sys; print(f'{(float(sys.argv[1])-float(sys.argv[2]))/3600:.3f}')" "$stamp" "$t0")
  printf '%s\t%s\t%.1f\n' "$(( $(date +%s) - start ))" "$data_h" "$(echo "$rss_kb/1024" | bc -l)" | tee -a "$out/rss.tsv"
done
trap - EXIT
wait "$pid" || { echo "soak: groundline serve failed; see $out/serve.log" >&2; exit 1; }
python3 - "$out/rss.tsv" "$hours" <<'EOF'
import csv, statistics, sys
rows = [(float(r["data_h"]), float(r["rss_mb"])) for r in csv.DictReader(open(sys.argv[1]), delimiter="\t")]
hours = float(sys.argv[2])
if not rows:
    sys.exit("soak: no samples (the run ended within the first sample period)")
# A single sample lands anywhere in the swing of transient buffers (a
# recovery search's grids, a renewed scan odometry), so each hour of data is
# summarised by its min, median and max; the growth is that of the median and
# of the max (the high-water) from the second hour to the last.
print("soak: RSS per hour of data [MB]: hour, samples, min, median, max")
by_hour = {}
for h, mb in rows:
    by_hour.setdefault(int(h), []).append(mb)
for k in sorted(by_hour):
    v = by_hour[k]
    print(f"soak:   {k}-{k + 1} h  {len(v):4d}  {min(v):6.1f}  {statistics.median(v):6.1f}  {max(v):6.1f}")
def at(h):
    return min(rows, key=lambda r: abs(r[0] - h))
a, b = at(1.0), at(hours)
print(f"soak: RSS {a[1]:.1f} MB at {a[0]:.2f} h, {b[1]:.1f} MB at {b[0]:.2f} h of data: "
      f"growth {100 * (b[1] - a[1]) / a[1]:+.1f} %  (max {max(r[1] for r in rows):.1f} MB)")
# The last full hour: the run's final sample may open an hour of its own.
last_hour = max([k for k in by_hour if k + 1 <= hours] or [max(by_hour)])
if 1 in by_hour and last_hour > 1:
    first, last = by_hour[1], by_hour[last_hour]
    g_med = 100 * (statistics.median(last) - statistics.median(first)) / statistics.median(first)
    g_max = 100 * (max(last) - max(first)) / max(first)
    print(f"soak: from hour 1-2 to hour {last_hour}-{last_hour + 1}: median {g_med:+.1f} %, "
          f"max {g_max:+.1f} %")
EOF
