#!/usr/bin/env bash
# DDS demo: the localization service between ROS 2-compatible topics.
#   1. simulate 60 m of zone B (seed 3, floor camera at 2 Hz);
#   2. the file replay of it through `groundline serve` (inputs.replay) at real time;
#   3. the same dataset as ROS 2 topics (`groundline replay-dds`, wall-clock stamps,
#      /odom, /scan, /camera/image_raw) -> `groundline serve` (inputs.dds,
#      output.dds) -> a listener process on /groundline/pose and /tf;
#   4. prints the accuracy of both against the ground truth (`groundline eval`),
#      what was published and received per topic, and the latencies.
#
# Network: loopback only. CYCLONEDDS_URI is set to samples/cyclonedds_loopback.xml
# (127.0.0.1, no multicast), and a domain id of its own (default 42) keeps the
# demo apart from other ROS 2 traffic on this machine. The service reads the
# sensor topics with ROS 2's sensor-data QoS (best effort, depth 5), as it would
# on a robot.
#   scripts/dds_demo.sh [--length 60m]
# Environment: GROUNDLINE_JOBS (build parallelism), GROUNDLINE_DDS_DEMO_OUT
# (default /tmp/groundline_dds_demo), ROS_DOMAIN_ID (default 42).
set -euo pipefail
cd "$(dirname "$0")/.."
length=60m
if [[ "${1:-}" == "--length" ]]; then length="$2"; fi

export CYCLONEDDS_URI="file://$PWD/samples/cyclonedds_loopback.xml"
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-42}"
out="${GROUNDLINE_DDS_DEMO_OUT:-/tmp/groundline_dds_demo}"
data="$out/zone_b_seed3_$length"
mkdir -p "$out"

echo "== building groundline and the pose listener =="
scripts/build.sh release groundline service_dds_pose_listener
gl="$PWD/build/tools/groundline"
listen="$PWD/build/tests/service/service_dds_pose_listener"

if [[ ! -f "$data/manifest.yaml" ]]; then
  echo "== simulating zone B, $length, seed 3; floor camera at 2 Hz =="
  "$gl" sim --zone B --length "$length" --seed 3 --camera-rate 2 --out "$data"
fi

echo "== file replay at real time (inputs.replay) =="
cat > "$out/serve_file.yaml" <<EOF
inputs:
  replay: {dataset: $data, speed: 1}
localizer: {preset: fusion}
start: {resume: false}
output: {dir: $out/file}
http: {enabled: false}
EOF
"$gl" serve --config "$out/serve_file.yaml"

echo "== DDS: replay-dds -> serve -> listener (domain $ROS_DOMAIN_ID) =="
cat > "$out/serve_dds.yaml" <<EOF
inputs:
  replay: {dataset: $data}   # calibration, floor map and start pose only
  dds: {odometry: odom, scan: true, image: true, initial_pose: true}
localizer: {preset: fusion}
start: {resume: false}
output:
  dir: $out/dds
  dds: {pose: true, tf: true, diagnostics: true}
http: {port: 0}
EOF
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
"$gl" serve --config "$out/serve_dds.yaml" > "$out/serve_dds.log" 2>&1 &
serve=$!; pids+=("$serve")
"$listen" --out "$out/listened_wall.tum" --timeout 3600 > "$out/listener.log" 2>&1 &
listener=$!; pids+=("$listener")
for _ in $(seq 1 600); do
  grep -q "listener: matched" "$out/listener.log" && break
  sleep 0.1
done
grep -q "listener: matched" "$out/listener.log" || { echo "the service did not come up:"; cat "$out/serve_dds.log"; exit 1; }
"$gl" replay-dds "$data" --rate 1 --stamps wall --odometry odom --images \
  --wait-for-subscribers 30 | tee "$out/replay.log"
sleep 1
kill -TERM "$serve"; wait "$serve"
kill -TERM "$listener"; wait "$listener"
trap - EXIT

# The listener's stamps are wall-clock ones: back to the dataset's clock.
offset=$(sed -n 's/.*stamps are the dataset.s plus \([0-9.]*\) s.*/\1/p' "$out/replay.log")
awk -v o="$offset" '{ printf "%.9f", $1 - o; for (i = 2; i <= NF; ++i) printf " %s", $i; print "" }' \
  "$out/listened_wall.tum" > "$out/listened.tum"

echo "== accuracy against the ground truth (keyframe poses) =="
"$gl" eval --dataset "$data" --est "$out/file/trajectory.tum" --label file_replay \
  --est "$out/listened.tum" --label dds_chain --json "$out/eval.json" | grep -Ei "^ *(label|ate|along|cross|heading|matched)"
echo "== messages =="
grep "published" "$out/replay.log"
python3 - "$out" <<'EOF'
import json, re, sys
out = sys.argv[1]
s = json.load(open(f"{out}/dds/summary.json"))
f = json.load(open(f"{out}/file/summary.json"))
for topic, c in s["dds"]["inputs"].items():
    if c["received"] or c["matched_writers"]:
        print(f"  service {topic:13s} received {c['received']:6d} accepted {c['accepted']:6d} dropped {c['dropped']:3d} {c['last_drop_reason']}")
o = s["dds"]["outputs"]
print(f"  service published poses {o['poses']} tf {o['tf']} diagnostics {o['diagnostics']}")
listener = open(f"{out}/listener.log").read().strip().splitlines()[-1]
print(f"  listener {listener}")
print("== latency ==")
print(f"  frame in memory -> keyframe (service, median / p99 ms): file replay "
      f"{f['latency_ms']['median']:.1f} / {f['latency_ms']['p99']:.1f}, DDS "
      f"{s['latency_ms']['median']:.1f} / {s['latency_ms']['p99']:.1f}")
m = re.search(r"pose_latency_ms median ([\d.]+) p99 ([\d.]+) tf_latency_ms median ([\d.]+) p99 ([\d.]+)", listener)
print(f"  keyframe stamp -> pose received (listener): median {m.group(1)} ms, p99 {m.group(2)} ms")
print(f"  odometry stamp -> map->odom received (listener): median {m.group(3)} ms, p99 {m.group(4)} ms")
EOF
