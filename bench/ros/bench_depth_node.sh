#!/usr/bin/env bash
# Latency benchmark of the depth completion node (not a test): starts the standalone node with the
# radar parameters, feeds VoD frame 08350 (radar + 1936x1216 image) at 15 Hz and prints one JSON
# line per output stride. Usage: bench/ros/bench_depth_node.sh [BUILD_DIR] [STRIDES...]
#   e.g. bench/ros/bench_depth_node.sh build_ros 1 2 4
# Environment: MODEL (default ground_gp, config/radar.yaml's), RATE (15 Hz), FRAMES (150),
# WITH_POINTS=1 also subscribes to the coloured cloud.
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
  sed -e "s/^stride: .*/stride: $stride/" -e "s/^model: .*/model: ${MODEL:-ground_gp}/" \
    config/radar.yaml > "$params"
  start_launch bench_depth_node_launch depth_completion.launch params:="$params"
  echo -n "stride $stride: "
  "$BENCH_BIN/bench_depth_node" --vod-root "$VOD_ROOT" --frame 08350 \
    --rate "$RATE" --frames "$FRAMES" --with-points "${WITH_POINTS:-0}"
  stop_launch
  rm -f "$params"
done
