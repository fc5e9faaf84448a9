#!/usr/bin/env bash
# Latency benchmark of the depth completion node (not a test): starts the standalone node with
# config/SENSOR.yaml, feeds a VoD frame (radar: 08350 with its 1936x1216 image, scan and image
# together at RATE; LiDAR: 00549, scans at POINTS_RATE and images at RATE with their own stamps)
# and prints one JSON line per output stride. Usage: bench/ros/bench_depth_node.sh [BUILD_DIR]
# [STRIDES...]
#   e.g. bench/ros/bench_depth_node.sh build_ros 1 2 4
#        SENSOR=lidar bench/ros/bench_depth_node.sh build 1
# Environment: SENSOR (radar | lidar), MODEL (default: the config's), RATE (camera, 15 Hz),
# POINTS_RATE (LiDAR, 10 Hz), FRAMES (scans, 150), WITH_POINTS=1 also subscribes to the coloured
# cloud, EXTRA_PARAMS YAML lines (separated by ';') appended to the config, for parameters it does
# not set (e.g. EXTRA_PARAMS='guided_ground_gp_prior: true').
cd "$(dirname "$0")/../.."
BUILD_DIR=${1:-build}
shift || true
STRIDES=${*:-2}
source bench/ros/launch_helpers.sh
VOD_ROOT=${VOD_ROOT:-${MMNVS_DATA_DIR:-$(pwd)/../shared/data}/vod}
RATE=${RATE:-15}
FRAMES=${FRAMES:-150}

for stride in $STRIDES; do
  params=$(mktemp --suffix=.yaml)
  edits=(-e "s/^stride: .*/stride: $stride/")
  [[ -n "${MODEL:-}" ]] && edits+=(-e "s/^model: .*/model: $MODEL/")
  sed "${edits[@]}" "config/${SENSOR:-radar}.yaml" > "$params"
  [[ -n "${EXTRA_PARAMS:-}" ]] && tr ';' '\n' <<< "$EXTRA_PARAMS" >> "$params"
  start_launch bench_depth_node_launch depth_completion.launch params:="$params"
  echo -n "stride $stride: "
  "$BENCH_BIN/bench_depth_node" --vod-root "$VOD_ROOT" --sensor "${SENSOR:-radar}" \
    --rate "$RATE" --points-rate "${POINTS_RATE:-10}" --frames "$FRAMES" \
    --with-points "${WITH_POINTS:-0}"
  stop_launch
  rm -f "$params"
done
