#!/usr/bin/env bash
# Latency benchmark of the depth completion node (not a test): starts the standalone node with the
# radar parameters, feeds VoD frame 08350 (radar + 1936x1216 image) at 15 Hz and prints one JSON
# line per output stride. Usage: bench/ros/bench_depth_node.sh [BUILD_DIR] [STRIDES...]
#   e.g. bench/ros/bench_depth_node.sh build_ros 1 2 4
# Environment: MODEL (default ground_gp, config/radar.yaml's), RATE (15 Hz), FRAMES (150),
# WITH_POINTS=1 also subscribes to the coloured cloud.
set -eo pipefail  # no -u: catkin's setup scripts read unset variables
cd "$(dirname "$0")/../.."
BUILD_DIR=${1:-build}
shift || true
STRIDES=${*:-2}
export PATH=/usr/bin:/bin:$PATH
# shellcheck disable=SC1091
source "$BUILD_DIR/devel/setup.bash"
export ROS_HOME=${ROS_HOME:-$(pwd)/$BUILD_DIR/ros_home}
export ROS_LOG_DIR=${ROS_LOG_DIR:-$ROS_HOME/log}
mkdir -p "$ROS_LOG_DIR"
PORT=${BENCH_ROS_PORT:-11411}
export ROS_MASTER_URI=http://localhost:$PORT
VOD_ROOT=${VOD_ROOT:-${MMNVS_DATA_DIR:-$(pwd)/../shared/data}/vod}
RATE=${RATE:-15}
FRAMES=${FRAMES:-150}

for stride in $STRIDES; do
  params=$(mktemp --suffix=.yaml)
  sed -e "s/^stride: .*/stride: $stride/" -e "s/^model: .*/model: ${MODEL:-ground_gp}/" \
    config/radar.yaml > "$params"
  roslaunch -p "$PORT" multimodal_nvs depth_completion.launch params:="$params" \
    > "$ROS_LOG_DIR/bench_depth_node_launch.log" 2>&1 &
  launch_pid=$!
  trap 'kill -INT $launch_pid 2>/dev/null || true' EXIT
  sleep 3
  echo -n "stride $stride: "
  "$BUILD_DIR/devel/lib/multimodal_nvs/bench_depth_node" --vod-root "$VOD_ROOT" --frame 08350 \
    --rate "$RATE" --frames "$FRAMES" --with-points "${WITH_POINTS:-0}"
  kill -INT $launch_pid
  wait $launch_pid || true
  trap - EXIT
  rm -f "$params"
done
