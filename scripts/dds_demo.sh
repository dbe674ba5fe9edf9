#!/usr/bin/env bash
# DDS demo skeleton: simulate a short zone B run (60 m, seed 3, floor camera at
# 2 Hz), replay it as ROS 2 topics with `groundline replay-dds`, and receive it
# in a second process (io_dds_listener) that prints what arrived per topic.
# Later the localization service sits between the two: it subscribes to the
# replay and publishes the pose, which the listener's place is taken by.
#
# Network: loopback only. CYCLONEDDS_URI is set to samples/cyclonedds_loopback.xml
# (127.0.0.1, no multicast), and a domain id of its own (default 42) keeps the
# demo apart from other ROS 2 traffic on this machine.
#   scripts/dds_demo.sh [--rate N]      (default: 4x real time)
# Environment: GROUNDLINE_JOBS (build parallelism), GROUNDLINE_DDS_DEMO_OUT
# (default /tmp/groundline_dds_demo), ROS_DOMAIN_ID (default 42).
set -euo pipefail
cd "$(dirname "$0")/.."
rate=4
if [[ "${1:-}" == "--rate" ]]; then rate="$2"; fi

export CYCLONEDDS_URI="file://$PWD/samples/cyclonedds_loopback.xml"
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-42}"
out="${GROUNDLINE_DDS_DEMO_OUT:-/tmp/groundline_dds_demo}"

echo "== building groundline and the DDS listener =="
scripts/build.sh release groundline io_dds_listener
gl=build/tools/groundline

if [[ ! -f "$out/zone_b_seed3/manifest.yaml" ]]; then
  echo "== simulating zone B, 60 m, seed 3; floor camera at 2 Hz =="
  "$gl" sim --zone B --length 60m --seed 3 --camera-rate 2 --out "$out/zone_b_seed3"
fi

echo "== listening (domain $ROS_DOMAIN_ID) =="
build/tests/io/io_dds_listener --idle 3 --timeout 600 &
listener=$!
trap 'kill "$listener" 2>/dev/null || true' EXIT

echo "== replaying at ${rate}x: /odom, /joint_states, /scan, /camera/image_raw, /tf_static =="
# Dataset stamps: at rates other than 1x, wall-clock stamps would run ahead of the clock.
"$gl" replay-dds "$out/zone_b_seed3" --rate "$rate" --stamps dataset --images \
  --wait-for-subscribers 30

# The listener's exit code is the demo's: 0 when odometry, joint states and scans arrived.
trap - EXIT
wait "$listener"
