#!/usr/bin/env bash
# Latency benchmark of the conditioning renderer in tf mode (not a test): starts the standalone node
# with config/renderer.yaml and drives it with bench_renderer (a 1216x1936 camera with depth on a
# stride grid, moving forward, at 5 Hz), one line per stride. Usage:
#   bench/ros/bench_renderer.sh [BUILD_DIR] [STRIDES...]      (default stride 2)
# Environment: FRAMES (40), RATE (5 Hz), PREVIEW=1 also subscribes to conditioning/preview,
# DEPTH_EVERY=N sends a depth set with every N-th image only (the live view follows the camera).
cd "$(dirname "$0")/../.."
BUILD_DIR=${1:-build}
shift || true
STRIDES=${*:-2}
source bench/ros/launch_helpers.sh

for stride in $STRIDES; do
  start_launch bench_renderer_launch conditioning_renderer.launch trajectory_source:=tf
  echo -n "stride $stride: "
  "$BENCH_BIN/bench_renderer" 1216 1936 "$stride" "${FRAMES:-40}" "${RATE:-5}" "${PREVIEW:-0}" "${DEPTH_EVERY:-1}"
  stop_launch
done
